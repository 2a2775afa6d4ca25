// Which directions each point may move in during an implicit solve: pinned points not at all,
// free points in any direction, points held on their contact plane (the floor or an obstacle
// face, contact_planes.h) only along it (Baraff and Witkin 1998's filter S = I - n n^T), and
// the components a condition holds (a roller) not along those. The solvers filter residuals and search directions with it, so
// the constraints hold exactly at every iterate.
#pragma once

#include "softbody/common/geometry.h"
#include "softbody/massspring/contact_planes.h"
#include "softbody/scene/boundary_conditions.h" // AxisMask

#include <vector>

namespace softbody
{

enum class PointMotion : char
{
  Fixed,
  Free,
  OnPlane ///< slides along its contact plane (MotionFilter::planes)
};

struct MotionFilter
{
  std::vector<PointMotion> motion;
  /// Each point's contact plane (null: none; OnPlane points need one).
  const ContactPlanes* planes = nullptr;
  /// Per point, the components held by conditions (null: none is).
  const std::vector<AxisMask>* heldAxes = nullptr;

  Vec3 apply(std::size_t i, const Vec3& v) const
  {
    Vec3 out = v;
    switch (motion[i])
    {
      case PointMotion::Fixed:
        return Vec3::Zero();
      case PointMotion::OnPlane:
      {
        const Vec3& normal = planes->of(i).normal;
        out = v - normal.dot(v) * normal;
        break;
      }
      case PointMotion::Free:
        break;
    }
    if (heldAxes)
    {
      const AxisMask held = (*heldAxes)[i];
      for (int axis = 0; axis < 3; ++axis)
      {
        out[axis] = (held & (1u << axis)) ? 0.0 : out[axis];
      }
    }
    return out;
  }
  bool moves(std::size_t i) const { return motion[i] != PointMotion::Fixed; }
};

} // namespace softbody
