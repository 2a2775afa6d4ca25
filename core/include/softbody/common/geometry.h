// Small geometric kernels on tetrahedra, shared by the models, the mesh checks and the tests.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry> // cross products

#include <array>
#include <cstdint>

namespace softbody
{

using Vec3 = Eigen::Vector3d;
/// Four point indices. Positive orientation: (p1-p0) . ((p2-p0) x (p3-p0)) > 0.
using Tet = std::array<std::int32_t, 4>;

/// Signed volume V = (1/6) (p1-p0) . ((p2-p0) x (p3-p0)) [m^3]; positive for positive orientation.
inline double signedTetVolume(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3)
{
  return (p1 - p0).dot((p2 - p0).cross(p3 - p0)) / 6.0;
}

/// Gradients dV/dp_i of the signed volume [m^2]. They sum to zero (translation invariance) and
/// sum_i p_i x g_i = 0 (rotation invariance), which is why volume forces along them conserve
/// linear and angular momentum.
inline std::array<Vec3, 4> tetVolumeGradients(
  const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3)
{
  const Vec3 e1 = p1 - p0, e2 = p2 - p0, e3 = p3 - p0;
  const Vec3 g1 = e2.cross(e3) / 6.0;
  const Vec3 g2 = e3.cross(e1) / 6.0;
  const Vec3 g3 = e1.cross(e2) / 6.0;
  return { -(g1 + g2 + g3), g1, g2, g3 };
}

} // namespace softbody
