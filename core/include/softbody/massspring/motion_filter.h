// Which directions each point may move in during an implicit solve: pinned points not at all,
// free points in any direction, points held on the floor only along it (Baraff and Witkin
// 1998's filter S = I - n n^T). The solvers filter residuals and search directions with it, so
// the constraints hold exactly at every iterate.
#pragma once

#include "softbody/common/geometry.h"

#include <vector>

namespace softbody
{

enum class PointMotion : char
{
  Fixed,
  Free,
  OnPlane ///< slides along the plane with normal MotionFilter::normal
};

struct MotionFilter
{
  std::vector<PointMotion> motion;
  Vec3 normal = Vec3::UnitZ(); ///< unit normal of the plane OnPlane points slide on

  Vec3 apply(std::size_t i, const Vec3& v) const
  {
    switch (motion[i])
    {
      case PointMotion::Fixed:
        return Vec3::Zero();
      case PointMotion::OnPlane:
        return v - normal.dot(v) * normal;
      case PointMotion::Free:
        break;
    }
    return v;
  }
  bool moves(std::size_t i) const { return motion[i] != PointMotion::Fixed; }
};

} // namespace softbody
