// Which points start inside another body (start_overlap.h). Per closed body: its triangles
// binned by their xy extent (a vertical ray from a point meets only the triangles of its cell)
// and a BVH for the distance to its surface; each point of another body within its box is
// inside when the ray up from it crosses the surface an odd number of times.
#include "softbody/collision/start_overlap.h"

#include "softbody/collision/closest_point.h"
#include "softbody/collision/triangle_bvh.h"
#include "softbody/common/parallel.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

namespace softbody
{
namespace
{

using Triangle = std::array<std::int32_t, 3>;

/// One body's closed surface, ready for inside tests.
class ClosedSurface
{
public:
  ClosedSurface(const std::vector<Triangle>& triangles, const std::vector<Vec3>& x)
    : Triangles(triangles)
    , X(x)
  {
    std::vector<Aabb> boxes(triangles.size());
    for (std::size_t t = 0; t < triangles.size(); ++t)
    {
      for (std::int32_t v : triangles[t])
      {
        boxes[t].grow(x[v]);
      }
      Box.grow(boxes[t]);
    }
    Bvh.build(boxes);
    // About one triangle per cell on a square-ish grid over the xy extent.
    Cells = std::max<std::size_t>(1, static_cast<std::size_t>(std::sqrt(static_cast<double>(triangles.size()))));
    const Vec3 size = Box.hi - Box.lo;
    CellSize = std::max({ size.x(), size.y(), 1e-12 }) / static_cast<double>(Cells);
    // Off the mesh's own coordinates, so that a ray does not run exactly through an edge (it
    // would be counted in both triangles, or in neither).
    Shift = 1e-7 * std::max(size.norm(), 1e-12) * Vec3(0.5773502691896258, 0.3141592653589793, 0.0);
    std::vector<std::vector<std::int32_t>> bins(Cells * Cells);
    for (std::size_t t = 0; t < triangles.size(); ++t)
    {
      const auto [i0, j0] = cell(boxes[t].lo);
      const auto [i1, j1] = cell(boxes[t].hi);
      for (std::size_t j = j0; j <= j1; ++j)
        for (std::size_t i = i0; i <= i1; ++i)
          bins[j * Cells + i].push_back(static_cast<std::int32_t>(t));
    }
    Start.push_back(0);
    for (const auto& bin : bins)
    {
      Items.insert(Items.end(), bin.begin(), bin.end());
      Start.push_back(Items.size());
    }
  }

  bool inside(const Vec3& p) const
  {
    if (Box.squaredDistance(p) > 0.0)
    {
      return false;
    }
    const Vec3 q = p + Shift;
    const auto [i, j] = cell(q);
    std::size_t crossings = 0;
    for (std::size_t k = Start[j * Cells + i]; k < Start[j * Cells + i + 1]; ++k)
    {
      const Triangle& t = Triangles[static_cast<std::size_t>(Items[k])];
      const Vec3 &a = X[t[0]], &b = X[t[1]], &c = X[t[2]];
      // q's barycentric coordinates in the triangle's xy projection.
      const double area = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
      if (area == 0.0)
      {
        continue; // vertical: the ray runs along it
      }
      const double u = ((b.x() - q.x()) * (c.y() - q.y()) - (c.x() - q.x()) * (b.y() - q.y())) / area;
      const double v = ((c.x() - q.x()) * (a.y() - q.y()) - (a.x() - q.x()) * (c.y() - q.y())) / area;
      const double w = 1.0 - u - v;
      if (u > 0.0 && v > 0.0 && w > 0.0 && u * a.z() + v * b.z() + w * c.z() > q.z())
      {
        ++crossings;
      }
    }
    return crossings % 2 == 1;
  }

  /// Distance from p to the surface: the BVH asked within a radius doubled until it answers.
  double distance(const Vec3& p) const
  {
    double radius = std::max(CellSize, 1e-9), best = std::numeric_limits<double>::infinity();
    for (int grow = 0; grow < 64 && !(best <= radius); ++grow) // 2^64 cells: beyond any finite scene
    {
      Bvh.forEachNear(p, radius, [&](std::int32_t item) {
        const Triangle& t = Triangles[static_cast<std::size_t>(item)];
        best = std::min(best, (p - closestPointOnTriangle(p, X[t[0]], X[t[1]], X[t[2]]).point).norm());
      });
      radius *= 2.0;
    }
    return best;
  }

private:
  std::array<std::size_t, 2> cell(const Vec3& p) const
  {
    auto index = [&](double value, double lo) {
      const double k = std::floor((value - lo) / CellSize);
      return static_cast<std::size_t>(std::clamp(k, 0.0, static_cast<double>(Cells - 1)));
    };
    return { index(p.x(), Box.lo.x()), index(p.y(), Box.lo.y()) };
  }

  std::vector<Triangle> Triangles;
  const std::vector<Vec3>& X;
  Aabb Box;
  TriangleBvh Bvh;
  std::size_t Cells = 1;
  double CellSize = 1.0;
  Vec3 Shift = Vec3::Zero();
  std::vector<std::size_t> Start; ///< cell c's triangles: Items[Start[c] .. Start[c + 1])
  std::vector<std::int32_t> Items;
};

std::string metres(double value)
{
  std::ostringstream text;
  text << std::setprecision(3) << value << " m";
  return text.str();
}

} // namespace

std::vector<StartOverlap> findStartOverlaps(const CollisionGeometry& geometry, const std::vector<Vec3>& positions)
{
  // The closed surfaces: one-sided triangles (tet boundaries), by body.
  std::map<std::int32_t, std::vector<Triangle>> surfaces;
  for (std::size_t t = 0; t < geometry.surfaceTriangles.size(); ++t)
  {
    if (geometry.twoSided.empty() || geometry.twoSided[t] == 0)
    {
      const Triangle& triangle = geometry.surfaceTriangles[t];
      surfaces[geometry.bodyOf[static_cast<std::size_t>(triangle[0])]].push_back(triangle);
    }
  }
  const std::vector<std::int32_t>& points = geometry.collidingPoints;
  std::map<std::pair<std::int32_t, std::int32_t>, StartOverlap> found;
  std::vector<double> depth(points.size());
  for (const auto& [outer, triangles] : surfaces)
  {
    const ClosedSurface surface(triangles, positions);
    parallelFor(points.size(), 256, [&](std::size_t k) {
      const auto i = static_cast<std::size_t>(points[k]);
      depth[k] = geometry.bodyOf[i] != outer && surface.inside(positions[i]) ? surface.distance(positions[i]) : -1.0;
    });
    for (std::size_t k = 0; k < points.size(); ++k) // in point order: the same at any thread count
    {
      if (depth[k] >= 0.0)
      {
        const std::int32_t inner = geometry.bodyOf[static_cast<std::size_t>(points[k])];
        StartOverlap& o = found[{ inner, outer }];
        o.inner = inner;
        o.outer = outer;
        ++o.points;
        o.depth = std::max(o.depth, depth[k]);
      }
    }
  }
  std::vector<StartOverlap> out;
  for (const auto& entry : found)
  {
    out.push_back(entry.second);
  }
  return out;
}

std::string startOverlapWarning(const std::vector<StartOverlap>& overlaps)
{
  if (overlaps.empty())
  {
    return {};
  }
  double deepest = 0.0;
  std::ostringstream message;
  message << "Bodies start inside each other: ";
  for (std::size_t k = 0; k < overlaps.size(); ++k)
  {
    const StartOverlap& o = overlaps[k];
    deepest = std::max(deepest, o.depth);
    message << (k > 0 ? "; " : "") << o.points << (o.points == 1 ? " point" : " points") << " of body " << o.inner
            << " lie inside body " << o.outer << ", the deepest " << metres(o.depth) << " below its surface";
  }
  message << ". The contacts push them apart at up to " << kStartOverlapSeparationSpeed << " m/s (about "
          << std::setprecision(2) << deepest / kStartOverlapSeparationSpeed
          << " s for this depth). To start them separate, move the bodies apart by at least "
          << metres(deepest) << " to start them separate.";
  return message.str();
}

} // namespace softbody
