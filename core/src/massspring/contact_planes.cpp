#include "softbody/massspring/contact_planes.h"

#include "softbody/common/parallel.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace softbody
{

ContactPlanes::ContactPlanes(std::optional<FloorPlane> floor)
  : Floor(floor)
{
  if (Floor)
  {
    Planes.push_back(ContactPlane{ Floor->origin, Floor->normal.normalized(), Vec3::Zero() });
  }
}

void ContactPlanes::reset(std::size_t pointCount)
{
  Planes.resize(Floor ? 1 : 0);
  PlaneOf.assign(pointCount, Floor ? 0 : -1);
}

void ContactPlanes::followBodies(const std::vector<Vec3>& x)
{
  for (ContactPlane& plane : Planes)
  {
    if (plane.onBody())
    {
      Vec3 face = Vec3::Zero();
      for (std::size_t k = 0; k < 3; ++k)
      {
        face += plane.weights(static_cast<Eigen::Index>(k)) * x[static_cast<std::size_t>(plane.corners[k])];
      }
      plane.origin = face + plane.lift;
    }
  }
}

double ContactPlanes::depth(std::size_t i, const Vec3& x) const
{
  if (PlaneOf[i] < 0)
  {
    return std::numeric_limits<double>::infinity();
  }
  const ContactPlane& p = of(i);
  return (x - p.origin).dot(p.normal);
}

namespace
{

/// The plane a contact keeps its point in front of at the step's end, or none for the kinds
/// that couple two moving sides through more than one point (edge against edge: after the
/// step). Obstacle: the face's tangent plane at the closest point, where the obstacle is at the
/// step's end. PointTriangle: the other body's face where its explicit prediction puts it,
/// moving at its corners' start velocity.
std::optional<ContactPlane> planeOf(const Contact& c, const std::vector<Vec3>& predicted, const std::vector<Vec3>& velocities)
{
  if (c.kind == ContactKind::Obstacle)
  {
    return ContactPlane{ c.surfacePoint + c.thickness * c.normal, c.normal, c.surfaceVelocity };
  }
  if (c.kind != ContactKind::PointTriangle)
  {
    return std::nullopt;
  }
  Vec3 closest = Vec3::Zero(), velocity = Vec3::Zero();
  for (int k = 0; k < 3; ++k)
  {
    const auto corner = static_cast<std::size_t>(c.other[static_cast<std::size_t>(k)]);
    closest += c.barycentric[k] * predicted[corner];
    velocity += c.barycentric[k] * velocities[corner];
  }
  return ContactPlane{ closest + c.thickness * c.normal, c.normal, velocity, c.other,
    Vec3(c.barycentric[0], c.barycentric[1], c.barycentric[2]), c.thickness * c.normal };
}

/// Whether the point started in front of the contact's surface (where it was at the start).
bool startsInFront(const Contact& c, const std::vector<Vec3>& start)
{
  Vec3 surface = c.surfacePoint;
  if (c.kind == ContactKind::PointTriangle)
  {
    surface = c.barycentric[0] * start[static_cast<std::size_t>(c.other[0])] +
      c.barycentric[1] * start[static_cast<std::size_t>(c.other[1])] +
      c.barycentric[2] * start[static_cast<std::size_t>(c.other[2])];
  }
  return c.normal.dot(start[static_cast<std::size_t>(c.point)] - surface) >= 0.0;
}

} // namespace

void ContactPlanes::addContacts(const ContactSet& detected, const std::vector<Vec3>& start,
  const std::vector<Vec3>& predicted, const std::vector<Vec3>& velocities)
{
  // The contact set is sorted by point: each point's contacts are one run of it, read in
  // order, so the planes and their numbering do not depend on the thread count.
  for (std::size_t k = 0; k < detected.size();)
  {
    const std::int32_t point = detected[k].point;
    std::size_t end = k;
    bool someInFront = false;
    while (end < detected.size() && detected[end].point == point)
    {
      const Contact& c = detected[end];
      someInFront = someInFront ||
        ((c.kind == ContactKind::Obstacle || c.kind == ContactKind::PointTriangle) && startsInFront(c, start));
      ++end;
    }
    const auto i = static_cast<std::size_t>(point);
    double deepest = depth(i, predicted[i]);
    std::optional<ContactPlane> chosen;
    for (; k < end; ++k)
    {
      const Contact& c = detected[k];
      const std::optional<ContactPlane> plane = planeOf(c, predicted, velocities);
      if (!plane || (someInFront && !startsInFront(c, start)))
      {
        continue;
      }
      const double d = (predicted[i] - plane->origin).dot(plane->normal);
      if (d < deepest)
      {
        deepest = d;
        chosen = plane;
      }
    }
    if (chosen)
    {
      PlaneOf[i] = static_cast<std::int32_t>(Planes.size());
      Planes.push_back(*chosen);
    }
  }
}

ContactApproach fastestApproach(const ContactPlanes& planes, const std::vector<Vec3>& x0,
  const std::vector<Vec3>& v0, const std::vector<double>& inverseMass, double h)
{
  // The largest approach over size; ties keep the larger approach, then the larger size, so the
  // answer does not depend on the thread count.
  const auto worse = [](const ContactApproach& a, const ContactApproach& b) {
    const double ra = a.ratio(), rb = b.ratio();
    if (ra != rb)
    {
      return ra > rb ? a : b;
    }
    return std::tie(a.approach, a.size) >= std::tie(b.approach, b.size) ? a : b;
  };
  return parallelReduce(
    x0.size(), 4096, ContactApproach{},
    [&](std::size_t i) {
      if (inverseMass[i] == 0.0 || planes.pointCount() <= i || !planes.has(i))
      {
        return ContactApproach{};
      }
      // Only the motion's part: a point that starts behind its plane is put on it by the solve.
      const double approach = std::max(0.0,
        std::max(0.0, -planes.depth(i, x0[i] + h * v0[i])) - std::max(0.0, -planes.depth(i, x0[i])));
      return ContactApproach{ approach, planes.elementSize(i) };
    },
    worse);
}

LandingApproach floorLandingApproach(const ContactPlanes& planes, const FloorPlane& floor, const Vec3& gravity,
  const std::vector<Vec3>& x0, const std::vector<Vec3>& v0, const std::vector<double>& inverseMass,
  const std::vector<std::int32_t>& bodyOf, std::int32_t bodies, double h)
{
  const Vec3 n = floor.normal.normalized();
  const double towardFloor = -gravity.dot(n); // gravity's pull toward the plane [m/s^2]
  // Each body's lowest free point (the first smallest index on ties: no dependence on order).
  std::vector<std::size_t> lowest(static_cast<std::size_t>(bodies), x0.size());
  for (std::size_t i = 0; i < x0.size(); ++i)
  {
    std::size_t& l = lowest[static_cast<std::size_t>(bodyOf[i])];
    if (inverseMass[i] > 0.0 && (l == x0.size() || (x0[i] - x0[l]).dot(n) < 0.0))
    {
      l = i;
    }
  }
  LandingApproach worst;
  for (std::size_t i : lowest)
  {
    if (i == x0.size())
    {
      continue; // every point held
    }
    const double height = (x0[i] - floor.origin).dot(n);
    const double falling = -v0[i].dot(n); // > 0 toward the plane
    // Energy: the speed at the plane whichever way it starts (up first, or slowed by a gravity
    // pointing away from the floor).
    const double speed2 = falling * falling + 2.0 * towardFloor * height;
    if (!(height > 0.0) || (towardFloor <= 0.0 && falling <= 0.0) || !(speed2 > 0.0))
    {
      continue; // on the floor already, or never getting there
    }
    const double speed = std::sqrt(speed2);
    const LandingApproach landing{ ContactApproach{ speed * h, planes.elementSize(i) }, speed, height };
    if (landing.approach.ratio() > worst.approach.ratio())
    {
      worst = landing;
    }
  }
  return worst;
}

std::vector<double> pointElementSizes(const Topology& topology, const std::vector<Vec3>& rest)
{
  std::vector<double> sizes(topology.vertexCount, 0.0);
  parallelFor(topology.vertexCount, 4096, [&](std::size_t i) {
    const std::int32_t begin = topology.vertexEdges.offsets[i];
    const std::int32_t end = topology.vertexEdges.offsets[i + 1];
    double sum = 0.0;
    for (std::int32_t k = begin; k < end; ++k)
    {
      const Edge& e =
        topology.edges[static_cast<std::size_t>(topology.vertexEdges.items[static_cast<std::size_t>(k)])];
      sum += (rest[static_cast<std::size_t>(e.b)] - rest[static_cast<std::size_t>(e.a)]).norm();
    }
    sizes[i] = end > begin ? sum / (end - begin) : 0.0;
  });
  return sizes;
}

} // namespace softbody
