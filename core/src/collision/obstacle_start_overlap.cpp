// Which bodies start across an obstacle (start_overlap.h): each colliding point against the
// obstacle face nearest to it, found through a BVH asked within a growing radius.
#include "softbody/collision/start_overlap.h"

#include "softbody/collision/closest_point.h"
#include "softbody/collision/triangle_bvh.h"
#include "softbody/common/parallel.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

namespace softbody
{
namespace
{

/// Every edge shared by exactly two faces.
bool isClosed(const ObstacleSurface& surface)
{
  std::map<std::pair<std::int32_t, std::int32_t>, int> faces;
  for (const auto& t : surface.triangles)
  {
    for (int k = 0; k < 3; ++k)
    {
      ++faces[{ std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3]) }];
    }
  }
  return !faces.empty() && std::all_of(faces.begin(), faces.end(), [](const auto& e) { return e.second == 2; });
}

/// Signed distance of p to the surface where its nearest feature is a face's interior
/// (negative behind the face), NaN where it is an edge or a corner (no side to tell).
double signedFaceDistance(const Vec3& p, const ObstacleSurface& surface, const TriangleBvh& bvh, double startRadius)
{
  double best = std::numeric_limits<double>::infinity(), signedBest = std::numeric_limits<double>::quiet_NaN();
  for (double radius = startRadius; radius < 1e300 && !(best <= radius); radius *= 2.0)
  {
    bvh.forEachNear(p, radius, [&](std::int32_t item) {
      const auto& t = surface.triangles[static_cast<std::size_t>(item)];
      const Vec3 &a = surface.vertices[t[0]], &b = surface.vertices[t[1]], &c = surface.vertices[t[2]];
      const TrianglePoint closest = closestPointOnTriangle(p, a, b, c);
      const double distance = (p - closest.point).norm();
      if (distance < best)
      {
        best = distance;
        const Vec3 normal = (b - a).cross(c - a);
        signedBest = closest.feature == TriangleFeature::Face && normal.norm() > 0.0
          ? std::copysign(distance, normal.dot(p - closest.point))
          : std::numeric_limits<double>::quiet_NaN();
      }
    });
    if (bvh.itemCount() == 0)
    {
      break;
    }
  }
  return signedBest;
}

} // namespace

std::vector<ObstacleStartOverlap> findObstacleStartOverlaps(const CollisionGeometry& geometry,
  const std::vector<Vec3>& positions, const std::vector<ObstacleSurface>& obstacles)
{
  const std::vector<std::int32_t>& points = geometry.collidingPoints;
  std::map<std::pair<std::int32_t, std::int32_t>, ObstacleStartOverlap> found;
  std::vector<double> side(points.size());
  for (std::size_t o = 0; o < obstacles.size(); ++o)
  {
    const ObstacleSurface& surface = obstacles[o];
    std::vector<Aabb> boxes(surface.triangles.size());
    Aabb all;
    for (std::size_t t = 0; t < surface.triangles.size(); ++t)
    {
      for (std::int32_t v : surface.triangles[t])
      {
        boxes[t].grow(surface.vertices[static_cast<std::size_t>(v)]);
      }
      all.grow(boxes[t]);
    }
    if (boxes.empty())
    {
      continue;
    }
    TriangleBvh bvh;
    bvh.build(boxes);
    const double startRadius = std::max(1e-9, 1e-3 * (all.hi - all.lo).norm());
    parallelFor(points.size(), 256, [&](std::size_t k) {
      side[k] = signedFaceDistance(positions[static_cast<std::size_t>(points[k])], surface, bvh, startRadius);
    });
    const bool closed = isClosed(surface);
    for (std::size_t k = 0; k < points.size(); ++k) // in point order: the same at any thread count
    {
      if (std::isnan(side[k]))
      {
        continue;
      }
      const std::int32_t body = geometry.bodyOf[static_cast<std::size_t>(points[k])];
      ObstacleStartOverlap& entry = found[{ body, static_cast<std::int32_t>(o) }];
      entry.body = body;
      entry.obstacle = static_cast<std::int32_t>(o);
      entry.closed = closed;
      if (side[k] < 0.0)
      {
        ++entry.behind;
        entry.depth = std::max(entry.depth, -side[k]);
      }
      else
      {
        ++entry.inFront;
      }
    }
  }
  std::vector<ObstacleStartOverlap> out;
  for (const auto& [key, entry] : found)
  {
    if (entry.behind > 0 && (entry.closed || entry.inFront > 0))
    {
      out.push_back(entry);
    }
  }
  return out;
}

std::string obstacleStartOverlapWarning(const std::vector<ObstacleStartOverlap>& overlaps)
{
  if (overlaps.empty())
  {
    return {};
  }
  std::ostringstream message;
  message << std::setprecision(3) << "Bodies start inside obstacles: ";
  for (std::size_t k = 0; k < overlaps.size(); ++k)
  {
    const ObstacleStartOverlap& o = overlaps[k];
    message << (k > 0 ? "; " : "") << o.behind << (o.behind == 1 ? " point" : " points") << " of body " << o.body
            << " start behind the surface of obstacle " << o.obstacle << (o.closed ? " (inside it)" : "")
            << ", the deepest " << o.depth << " m";
  }
  message << ". The contacts push the points near the surface out to its free side and let deeper ones "
             "through from behind, so the body is pulled across it (tets may invert). Move the body to the "
             "obstacle's free side by at least that depth (or, for an open surface that faces the wrong way, "
             "Reverse Sense).";
  return message.str();
}

void noteObstacleStart(const CollisionDetector& detector, const std::vector<Vec3>& positions, double time,
  bool& checked, std::vector<std::string>& warnings)
{
  if (checked || time != 0.0 || detector.obstacles().empty())
  {
    return;
  }
  checked = true;
  const std::string warning =
    obstacleStartOverlapWarning(findObstacleStartOverlaps(detector.geometry(), positions, detector.obstacles()));
  if (!warning.empty())
  {
    warnings.push_back(warning);
  }
}

} // namespace softbody
