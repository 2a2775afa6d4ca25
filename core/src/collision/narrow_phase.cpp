#include "softbody/collision/narrow_phase.h"

#include <cmath>

namespace softbody
{

bool edgeEdgeContact(const EdgePair& predicted, const EdgePair& start, double thickness,
  double queryRadius, ContactCandidate& out)
{
  const SegmentPair w = closestPointsOfSegments(predicted.a0, predicted.a1, predicted.b0, predicted.b1);
  // The ends are the point-triangle contacts' (a vertex against the edge of a face); a
  // tolerance keeps a contact that is one by rounding from being counted twice.
  constexpr double kInside = 1e-6;
  if (w.s <= kInside || w.s >= 1.0 - kInside || w.t <= kInside || w.t >= 1.0 - kInside)
  {
    return false;
  }
  auto along = [](const Vec3& from, const Vec3& to, double weight) { return from + weight * (to - from); };
  const Vec3 offset = along(predicted.a0, predicted.a1, w.s) - along(predicted.b0, predicted.b1, w.t);
  const double distance = offset.norm();
  if (distance > queryRadius)
  {
    return false;
  }
  // The side is read at the start, from the closest points there (the edges slide along each
  // other during the substep: the predicted weights at the start positions would tilt the
  // normal by the slide over the gap, and a bar resting across a ridge would roll off it).
  const SegmentPair w0 = closestPointsOfSegments(start.a0, start.a1, start.b0, start.b1);
  const Vec3 startOffset = along(start.a0, start.a1, w0.s) - along(start.b0, start.b1, w0.t);
  const double startDistance = startOffset.norm();
  const Vec3 ea = start.a1 - start.a0, eb = start.b1 - start.b0;
  if (!(startDistance > 1e-9 * (ea.norm() + eb.norm())))
  {
    return false; // touching at the start: no side to keep
  }
  // Edges at an angle: the common perpendicular of their lines, which the closest points'
  // offset is along when both lie inside the edges, and which stays exact when one is at an
  // end. Nearly parallel edges: the offset itself.
  constexpr double kLeastSine = 0.05;
  const Vec3 perpendicular = ea.cross(eb);
  const double side = perpendicular.dot(startOffset);
  if (perpendicular.norm() > kLeastSine * ea.norm() * eb.norm() && side != 0.0)
  {
    out.contact.normal = (side > 0.0 ? 1.0 : -1.0) * perpendicular.normalized();
  }
  else
  {
    out.contact.normal = startOffset / startDistance;
  }
  out.contact.barycentric = Vec3(w.s, w.t, 0.0);
  out.contact.surfacePoint = Vec3::Zero(); // both sides move with their bodies
  out.contact.thickness = thickness;
  out.distance = distance;
  out.onFace = true; // one feature each: nothing for the reduction to merge
  out.behind = false;
  return true;
}

bool pointTriangleContact(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, double side,
  double thickness, double queryRadius, ContactCandidate& out)
{
  const TrianglePoint closest = closestPointOnTriangle(p, a, b, c);
  const Vec3 offset = p - closest.point;
  const double distance2 = offset.squaredNorm();
  if (distance2 > queryRadius * queryRadius)
  {
    return false;
  }
  const double distance = std::sqrt(distance2);
  const Vec3 area = (b - a).cross(c - a);
  const double areaNorm = area.norm();
  const bool onFace = closest.feature == TriangleFeature::Face;
  Vec3 normal;
  out.behind = false;
  if (areaNorm > 0.0)
  {
    normal = side * area / areaNorm;
    const double signedDistance = normal.dot(offset);
    if (signedDistance < 0.0)
    {
      // Behind, the triangle answers only where the point projects onto it, along the face
      // normal (pushed out the front). The projection may fall on an edge or corner (right
      // under the diagonal of a quad) where no neighbour has it in its face either, hence the
      // test on the tangential offset rather than on the feature. Elsewhere behind an edge or
      // corner, the neighbouring face answers.
      const Vec3 tangential = offset - signedDistance * normal;
      if (!onFace && tangential.norm() > 1e-9 * std::sqrt(areaNorm))
      {
        return false;
      }
      out.behind = true;
    }
    else if (!onFace && distance > 1e-12 * std::sqrt(areaNorm))
    {
      // On an edge or corner in front, the exact normal is the direction from the closest
      // point (C = |x - q| - thickness there), the face normal only right above the face.
      normal = offset / distance;
    }
  }
  else if (distance > 0.0)
  {
    normal = offset / distance; // degenerate triangle: no side, only the direction
  }
  else
  {
    return false; // a point on a zero-area triangle has no direction to be pushed
  }
  out.contact.normal = normal;
  out.contact.barycentric = closest.barycentric;
  out.contact.surfacePoint = closest.point;
  out.contact.thickness = thickness;
  out.distance = distance;
  out.onFace = onFace;
  return true;
}

bool pointPointContact(const Vec3& p, const Vec3& q, const Vec3& fallback, double thickness,
  double queryRadius, ContactCandidate& out)
{
  const Vec3 offset = p - q;
  const double distance2 = offset.squaredNorm();
  if (distance2 > queryRadius * queryRadius)
  {
    return false;
  }
  const double distance = std::sqrt(distance2);
  Vec3 normal = Vec3::UnitZ();
  if (distance > 0.0)
  {
    normal = offset / distance;
  }
  else if (fallback.squaredNorm() > 0.0)
  {
    normal = fallback.normalized();
  }
  out.contact.normal = normal;
  out.contact.surfacePoint = q;
  out.contact.thickness = thickness;
  out.distance = distance;
  out.onFace = true;
  return true;
}

bool pointPlaneContact(const Vec3& p, const Vec3& origin, const Vec3& normal, double thickness,
  double queryRadius, ContactCandidate& out)
{
  const double height = normal.dot(p - origin);
  if (height > queryRadius)
  {
    return false;
  }
  out.contact.normal = normal;
  out.contact.surfacePoint = p - height * normal;
  out.contact.thickness = thickness;
  out.distance = std::abs(height);
  out.onFace = true;
  return true;
}

double triangleSide(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c)
{
  const TrianglePoint closest = closestPointOnTriangle(p, a, b, c);
  return (p - closest.point).dot((b - a).cross(c - a)) >= 0.0 ? 1.0 : -1.0;
}

} // namespace softbody
