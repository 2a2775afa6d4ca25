#include "softbody/collision/narrow_phase.h"

#include <cmath>

namespace softbody
{

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
