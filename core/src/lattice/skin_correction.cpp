#include "softbody/lattice/skin_correction.h"

#include "softbody/collision/aabb.h"
#include "softbody/collision/narrow_phase.h"
#include "softbody/collision/triangle_bvh.h"
#include "softbody/common/errors.h"
#include "softbody/common/parallel.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

namespace softbody
{

SkinCorrection keepAboveFloor(const FloorPlane& floor, std::vector<Vec3>& vertices)
{
  const Vec3 n = floor.normal.normalized();
  SkinCorrection result;
  for (Vec3& x : vertices)
  {
    const double height = n.dot(x - floor.origin);
    if (height < 0.0)
    {
      x -= height * n;
      ++result.moved;
      result.deepest = std::max(result.deepest, -height);
    }
  }
  return result;
}

std::vector<double> skinReach(const Skin& skin, const std::vector<Vec3>& particlePositions,
  const std::vector<Vec3>& vertices)
{
  if (vertices.size() != skin.vertexCount())
  {
    throw std::invalid_argument("skinReach: one vertex per skinned vertex expected");
  }
  std::vector<double> reach(vertices.size(), 0.0);
  parallelFor(vertices.size(), 1024, [&](std::size_t v) {
    double farthest = 0.0;
    for (std::int32_t e = skin.offsets[v]; e < skin.offsets[v + 1]; ++e)
    {
      const Vec3& p = particlePositions[std::size_t(skin.particles[std::size_t(e)])];
      farthest = std::max(farthest, (p - vertices[v]).norm());
    }
    reach[v] = farthest;
  });
  return reach;
}

SkinCorrection keepOutsideObstacles(const std::vector<ObstacleSurface>& obstacles,
  const std::vector<double>& reach, std::vector<Vec3>& vertices)
{
  if (reach.size() != vertices.size())
  {
    throw std::invalid_argument("keepOutsideObstacles: one reach per vertex expected");
  }
  // All obstacles' triangles in one tree, items numbered (obstacle, triangle) in order.
  std::vector<std::array<std::int32_t, 2>> items;
  std::vector<Aabb> boxes;
  for (std::size_t o = 0; o < obstacles.size(); ++o)
  {
    const ObstacleSurface& surface = obstacles[o];
    for (std::size_t t = 0; t < surface.triangles.size(); ++t)
    {
      Aabb box;
      for (const std::int32_t corner : surface.triangles[t])
      {
        if (corner < 0 || std::size_t(corner) >= surface.vertices.size())
        {
          throw InvalidInputError("Obstacle " + std::to_string(o) + ", triangle " + std::to_string(t) +
            ": vertex index " + std::to_string(corner) + " is outside 0.." +
            std::to_string(surface.vertices.size()) + ".");
        }
        box.grow(surface.vertices[std::size_t(corner)]);
      }
      items.push_back({ static_cast<std::int32_t>(o), static_cast<std::int32_t>(t) });
      boxes.push_back(box);
    }
  }
  if (items.empty() || vertices.empty())
  {
    return {};
  }
  TriangleBvh bvh;
  bvh.build(boxes);

  // Per vertex its move (0 = untouched), summed afterwards in vertex order.
  std::vector<double> depth(vertices.size(), 0.0);
  parallelFor(vertices.size(), 256, [&](std::size_t v) {
    const Vec3 p = vertices[v];
    if (!(reach[v] > 0.0))
    {
      return;
    }
    // The closest triangle within reach under the narrow phase's one-sided rules (thickness 0:
    // the drawn surface goes onto the obstacle, not onto its margin). Ties keep the first item
    // visited; the tree and its visiting order are deterministic.
    ContactCandidate best;
    double bestDistance = std::numeric_limits<double>::infinity();
    bvh.forEachNear(p, reach[v], [&](std::int32_t item) {
      const auto [o, t] = items[std::size_t(item)];
      const ObstacleSurface& surface = obstacles[std::size_t(o)];
      const auto& tri = surface.triangles[std::size_t(t)];
      ContactCandidate candidate;
      if (pointTriangleContact(p, surface.vertices[std::size_t(tri[0])], surface.vertices[std::size_t(tri[1])],
            surface.vertices[std::size_t(tri[2])], 1.0, 0.0, reach[v], candidate) &&
        candidate.distance < bestDistance)
      {
        best = candidate;
        bestDistance = candidate.distance;
      }
    });
    if (bestDistance == std::numeric_limits<double>::infinity())
    {
      return;
    }
    const double signedDistance = best.contact.normal.dot(p - best.contact.surfacePoint);
    if (signedDistance < 0.0)
    {
      // Behind a face (the only feature that answers from behind): its closest point is the
      // projection along the face normal.
      vertices[v] = best.contact.surfacePoint;
      depth[v] = -signedDistance;
    }
  });
  SkinCorrection result;
  for (const double d : depth)
  {
    if (d > 0.0)
    {
      ++result.moved;
      result.deepest = std::max(result.deepest, d);
    }
  }
  return result;
}

} // namespace softbody
