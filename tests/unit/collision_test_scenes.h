// Scenes for the collision-detection tests: tet bodies and particle bodies assembled into one
// CollisionGeometry, and a field-by-field comparison of contact sets.
#pragma once

#include "softbody/collision/collision_detector.h"
#include "softbody/mesh/tet_mesh.h"

#include <set>

namespace softbody::test
{

/// Adds a tet body (its boundary triangles and their vertices collide) as body `body`.
inline void addTetBody(CollisionGeometry& g, const TetMesh& mesh, std::int32_t body)
{
  const auto offset = static_cast<std::int32_t>(g.rest.size());
  std::set<std::int32_t> surface;
  for (auto t : boundaryTriangles(mesh.tets))
  {
    for (auto& v : t)
    {
      v += offset;
      surface.insert(v);
    }
    g.surfaceTriangles.push_back(t);
  }
  for (const Vec3& p : mesh.points)
  {
    g.rest.push_back(p);
    g.bodyOf.push_back(body);
    g.radius.push_back(0.0);
  }
  g.collidingPoints.insert(g.collidingPoints.end(), surface.begin(), surface.end());
}

/// Adds particles of one radius as body `body`; all of them collide.
inline void addParticleBody(CollisionGeometry& g, const std::vector<Vec3>& centres, double radius, std::int32_t body)
{
  for (const Vec3& p : centres)
  {
    g.collidingPoints.push_back(static_cast<std::int32_t>(g.rest.size()));
    g.rest.push_back(p);
    g.bodyOf.push_back(body);
    g.radius.push_back(radius);
  }
}

/// Every field equal, bit for bit (doubles compared with ==, which is exact).
inline bool sameContact(const Contact& a, const Contact& b)
{
  return a.kind == b.kind && a.point == b.point && a.other == b.other && a.barycentric == b.barycentric &&
    a.normal == b.normal && a.surfacePoint == b.surfacePoint && a.surfaceVelocity == b.surfaceVelocity &&
    a.thickness == b.thickness && a.source == b.source;
}

inline bool sameContacts(const ContactSet& a, const ContactSet& b)
{
  if (a.size() != b.size())
  {
    return false;
  }
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    if (!sameContact(a[i], b[i]))
    {
      return false;
    }
  }
  return true;
}

/// A unit-square-based triangle pair in the plane z = height, normal +z (counter-clockwise
/// seen from above), spanning [-size, size]^2.
inline ObstacleSurface flatObstacle(double height, double size)
{
  ObstacleSurface s;
  s.vertices = { Vec3(-size, -size, height), Vec3(size, -size, height), Vec3(size, size, height),
    Vec3(-size, size, height) };
  s.triangles = { { 0, 1, 2 }, { 0, 2, 3 } };
  return s;
}

/// The closed surface of the axis-aligned box [lo, hi], 12 triangles wound outward.
inline ObstacleSurface boxObstacle(const Vec3& lo, const Vec3& hi)
{
  ObstacleSurface s;
  for (int k = 0; k < 8; ++k)
  {
    s.vertices.emplace_back((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(), (k & 4) ? hi.z() : lo.z());
  }
  // Quads (outward, counter-clockwise seen from outside), split along their first diagonal.
  const int quads[6][4] = { { 0, 2, 3, 1 }, { 4, 5, 7, 6 }, { 0, 1, 5, 4 }, { 2, 6, 7, 3 },
    { 0, 4, 6, 2 }, { 1, 3, 7, 5 } };
  for (const auto& q : quads)
  {
    s.triangles.push_back({ q[0], q[1], q[2] });
    s.triangles.push_back({ q[0], q[2], q[3] });
  }
  return s;
}

} // namespace softbody::test
