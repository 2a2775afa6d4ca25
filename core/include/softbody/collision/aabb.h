// Axis-aligned boxes for the broad phases.
#pragma once

#include "softbody/common/geometry.h"

#include <limits>

namespace softbody
{

struct Aabb
{
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = Vec3::Constant(-std::numeric_limits<double>::infinity());

  void grow(const Vec3& p)
  {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  void grow(const Aabb& box)
  {
    lo = lo.cwiseMin(box.lo);
    hi = hi.cwiseMax(box.hi);
  }
  void inflate(double amount)
  {
    lo.array() -= amount;
    hi.array() += amount;
  }
  /// Whether the two boxes share a point (touching counts).
  bool overlaps(const Aabb& box) const
  {
    return (lo.array() <= box.hi.array()).all() && (box.lo.array() <= hi.array()).all();
  }
  /// Squared distance from p to the box (0 inside).
  double squaredDistance(const Vec3& p) const
  {
    return (lo - p).cwiseMax(p - hi).cwiseMax(0.0).squaredNorm();
  }
};

} // namespace softbody
