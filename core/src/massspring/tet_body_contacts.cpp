// Contacts of mass-spring tet bodies: the detector's geometry, the plane the floor holds
// points on, and the lift that starts a body on it (tet_body_contacts.h).
#include "softbody/massspring/tet_body_contacts.h"

#include "softbody/collision/boundary_triangles.h"
#include "softbody/mesh/components.h"

#include <algorithm>
#include <numeric>

namespace softbody
{
std::vector<std::int32_t> bodyOfPoints(const TetMesh& mesh, std::int32_t& bodies)
{
  const Components components = tetComponents(mesh.points.size(), mesh.tets);
  std::vector<std::int32_t> bodyOf(mesh.points.size(), -1);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
  {
    for (std::int32_t v : mesh.tets[t])
    {
      bodyOf[v] = components.ofCell[t];
    }
  }
  bodies = components.count;
  for (std::int32_t& body : bodyOf)
  {
    body = body < 0 ? bodies++ : body;
  }
  return bodyOf;
}

/// What the detector collides of a tet body: its boundary triangles (outward), each point's
/// connected body; no particles (radius 0). The colliding points are all points, so that a
/// body crushed through its own bottom (a very soft one, a fast impact) still keeps every
/// point out of the floor and the obstacles; with self
/// collisions only the surface vertices, since an interior point lies behind its own
/// surface's one-sided triangles and would be pushed out through them.
CollisionGeometry tetBodyGeometry(const TetMesh& mesh, const CollisionSettings& collisions)
{
  CollisionGeometry g;
  g.rest = mesh.points;
  g.radius.assign(mesh.points.size(), 0.0);
  // Points in no tet belong to no body and collide with nothing: each has its own number.
  std::int32_t bodies = 0;
  g.bodyOf = bodyOfPoints(mesh, bodies);
  g.surfaceTriangles = boundaryTriangles(mesh.tets);
  if (!collisions.selfCollides())
  {
    g.collidingPoints.resize(mesh.points.size());
    std::iota(g.collidingPoints.begin(), g.collidingPoints.end(), 0);
    return g;
  }
  for (const auto& triangle : g.surfaceTriangles)
  {
    g.collidingPoints.insert(g.collidingPoints.end(), triangle.begin(), triangle.end());
  }
  std::sort(g.collidingPoints.begin(), g.collidingPoints.end());
  g.collidingPoints.erase(
    std::unique(g.collidingPoints.begin(), g.collidingPoints.end()), g.collidingPoints.end());
  return g;
}

FloorContact floorContactOf(const TetMesh& mesh, const Scene& scene)
{
  const CollisionDetector detector(tetBodyGeometry(mesh, scene.collisions), scene.collisions,
    scene.floorActive(), scene.floor);
  return FloorContact{ detector.floor(), detector.margin() };
}

std::size_t liftBodiesOntoPlane(const TetMesh& mesh, const std::vector<double>& inverseMass,
  const FloorPlane& plane, std::vector<Vec3>& positions)
{
  const Vec3 n = plane.normal.normalized();
  std::int32_t bodies = 0;
  const std::vector<std::int32_t> bodyOf = bodyOfPoints(mesh, bodies);
  std::vector<double> deepest(static_cast<std::size_t>(bodies), 0.0);
  std::vector<char> held(static_cast<std::size_t>(bodies), 0);
  for (std::size_t i = 0; i < positions.size(); ++i)
  {
    const auto b = static_cast<std::size_t>(bodyOf[i]);
    deepest[b] = std::min(deepest[b], n.dot(positions[i] - plane.origin));
    held[b] = held[b] || inverseMass[i] == 0.0;
  }
  std::size_t lifted = 0;
  for (std::size_t b = 0; b < deepest.size(); ++b)
  {
    if (held[b] || !(deepest[b] < 0.0))
    {
      deepest[b] = 0.0;
      continue;
    }
    ++lifted;
  }
  for (std::size_t i = 0; i < positions.size(); ++i)
  {
    positions[i] -= deepest[static_cast<std::size_t>(bodyOf[i])] * n;
  }
  return lifted;
}

} // namespace softbody
