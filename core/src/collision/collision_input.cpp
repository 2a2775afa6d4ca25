#include "softbody/collision/collision_input.h"

#include "softbody/common/errors.h"
#include "softbody/common/validation.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace softbody
{

namespace
{

std::string indexText(std::size_t index)
{
  return std::to_string(index);
}

} // namespace

void validateCollisionGeometry(const CollisionGeometry& g)
{
  const std::size_t n = g.rest.size();
  if (g.bodyOf.size() != n || g.radius.size() != n)
  {
    throw InvalidInputError("Collision geometry: " + indexText(n) + " rest positions but " +
      indexText(g.bodyOf.size()) + " body indices and " + indexText(g.radius.size()) + " radii.");
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    check::finite("Collision geometry rest position", g.rest[i]);
    if (!std::isfinite(g.radius[i]) || g.radius[i] < 0.0)
    {
      throw InvalidInputError("Collision geometry: the radius of point " + indexText(i) +
        " must be >= 0, got " + check::quote(g.radius[i]) + ".");
    }
  }
  auto checkIndex = [n](std::int32_t index, const char* what) {
    if (index < 0 || static_cast<std::size_t>(index) >= n)
    {
      throw InvalidInputError(std::string("Collision geometry: ") + what + " index " +
        std::to_string(index) + " is out of range [0, " + indexText(n) + ").");
    }
  };
  for (const auto& triangle : g.surfaceTriangles)
  {
    for (std::int32_t v : triangle)
    {
      checkIndex(v, "surface triangle vertex");
    }
  }
  for (std::int32_t p : g.collidingPoints)
  {
    checkIndex(p, "colliding point");
  }
  if (!g.twoSided.empty() && g.twoSided.size() != g.surfaceTriangles.size())
  {
    throw InvalidInputError("Collision geometry: " + indexText(g.twoSided.size()) +
      " two-sided flags for " + indexText(g.surfaceTriangles.size()) + " surface triangles.");
  }
}

void validateObstacles(const std::vector<ObstacleSurface>& obstacles, double endTime)
{
  if (!std::isfinite(endTime))
  {
    throw InvalidInputError("Obstacle end time must be finite, got " + check::quote(endTime) + ".");
  }
  for (std::size_t o = 0; o < obstacles.size(); ++o)
  {
    const ObstacleSurface& surface = obstacles[o];
    const std::string name = "Obstacle " + indexText(o);
    for (const Vec3& v : surface.vertices)
    {
      if (!v.allFinite())
      {
        throw InvalidInputError(name + " has a vertex that is not finite: " + check::quote(v) + ".");
      }
    }
    if (!surface.velocities.empty() && surface.velocities.size() != surface.vertices.size())
    {
      throw InvalidInputError(name + " has " + indexText(surface.velocities.size()) +
        " velocities for " + indexText(surface.vertices.size()) +
        " vertices (give none for a static obstacle, or one per vertex).");
    }
    for (const Vec3& v : surface.velocities)
    {
      if (!v.allFinite())
      {
        throw InvalidInputError(name + " has a velocity that is not finite: " + check::quote(v) + ".");
      }
    }
    for (const auto& triangle : surface.triangles)
    {
      for (std::int32_t index : triangle)
      {
        if (index < 0 || static_cast<std::size_t>(index) >= surface.vertices.size())
        {
          throw InvalidInputError(name + " has a triangle with vertex index " +
            std::to_string(index) + ", out of range [0, " + indexText(surface.vertices.size()) + ").");
        }
      }
    }
  }
}

double automaticMargin(const CollisionGeometry& g)
{
  double edgeSum = 0.0;
  std::size_t edges = 0;
  for (const auto& t : g.surfaceTriangles)
  {
    for (int k = 0; k < 3; ++k)
    {
      edgeSum += (g.rest[t[(k + 1) % 3]] - g.rest[t[k]]).norm();
      ++edges;
    }
  }
  double radiusSum = 0.0;
  std::size_t particles = 0;
  for (std::int32_t p : g.collidingPoints)
  {
    if (g.radius[p] > 0.0)
    {
      radiusSum += g.radius[p];
      ++particles;
    }
  }
  double margin = 0.0;
  if (edges > 0)
  {
    margin = 0.1 * edgeSum / static_cast<double>(edges);
  }
  if (particles > 0)
  {
    const double fromRadius = 0.1 * radiusSum / static_cast<double>(particles);
    margin = edges > 0 ? std::min(margin, fromRadius) : fromRadius;
  }
  return margin;
}


} // namespace softbody
