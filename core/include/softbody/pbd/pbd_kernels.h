// Projection kernels of position-based dynamics: pure functions of the particles' positions and
// inverse masses, one per constraint type, so each is tested on its own.
//
// Every kernel follows XPBD (Macklin, Mueller, Chentanez 2016). For a constraint C(x) with
// gradients g_k and compliance alpha, one projection computes
//     dLambda = (-C - alphaTilde * lambda) / (sum_k w_k |g_k|^2 + alphaTilde),  alphaTilde = alpha / h^2
//     dx_k    = w_k g_k dLambda
// With alphaTilde = 0 and lambda = 0 this is exactly the PBD projection of Mueller et al. 2007 at
// stiffness 1; PBD's stiffness k enters as the factor `scale` = 1 - (1 - k)^(1/n), and SOR's
// relaxation multiplies it too.
#pragma once

#include "softbody/common/geometry.h"

#include <array>
#include <cmath>

namespace softbody
{

/// What one projection asks of its N particles.
template <int N>
struct Projection
{
  Projection()
  {
    for (Vec3& v : dx)
    {
      v.setZero(); // Eigen leaves vectors uninitialized
    }
  }
  std::array<Vec3, N> dx;   ///< position corrections, already weighted by inverse mass
  double dLambda = 0.0;     ///< change of the Lagrange multiplier (XPBD); 0 when inactive
  double residual = 0.0;    ///< C + alphaTilde * lambda before the projection (0 if satisfied)
};

/// Per-projection constants of a batch within one step.
struct ProjectionParameters
{
  double scale = 1.0;      ///< PBD stiffness correction times relaxation (XPBD: relaxation)
  double alphaTilde = 0.0; ///< compliance / h^2 (PBD: 0)
};

namespace detail
{
/// The shared XPBD update for a constraint value C with denominator sum_k w_k |g_k|^2.
inline double lagrangeStep(double C, double weightedGradient2, double lambda,
  const ProjectionParameters& p, double& residual)
{
  if (p.scale == 0.0)
  {
    residual = 0.0; // a constraint of zero stiffness asks for nothing
    return 0.0;
  }
  residual = C + p.alphaTilde * lambda;
  const double denominator = weightedGradient2 + p.alphaTilde;
  if (!(denominator > 0.0))
  {
    return 0.0; // both ends pinned, or a degenerate gradient: nothing can move
  }
  return -p.scale * residual / denominator;
}
} // namespace detail

enum class DistanceKind
{
  Equality, ///< |x0 - x1| = rest
  AtLeast   ///< |x0 - x1| >= rest (only pushes apart)
};

/// Distance constraint C = |x0 - x1| - rest; gradients n and -n with n = (x0 - x1) / |x0 - x1|.
inline Projection<2> projectDistance(const Vec3& x0, const Vec3& x1, double w0, double w1,
  double rest, DistanceKind kind, double lambda, const ProjectionParameters& p)
{
  Projection<2> out;
  const Vec3 d = x0 - x1;
  const double length = d.norm();
  const double C = length - rest;
  if (length <= 0.0 || (kind == DistanceKind::AtLeast && C >= 0.0))
  {
    return out; // coincident points have no direction to move along
  }
  const Vec3 n = d / length;
  out.dLambda = detail::lagrangeStep(C, w0 + w1, lambda, p, out.residual);
  out.dx[0] = w0 * out.dLambda * n;
  out.dx[1] = -w1 * out.dLambda * n;
  return out;
}

/// Tet volume constraint C = V(x) - restVolume (signed volume, so an inverted tet is pushed back
/// through zero); gradients from tetVolumeGradients.
inline Projection<4> projectTetVolume(const std::array<Vec3, 4>& x, const std::array<double, 4>& w,
  double restVolume, double lambda, const ProjectionParameters& p)
{
  Projection<4> out;
  const double C = signedTetVolume(x[0], x[1], x[2], x[3]) - restVolume;
  const std::array<Vec3, 4> g = tetVolumeGradients(x[0], x[1], x[2], x[3]);
  double weightedGradient2 = 0.0;
  for (int k = 0; k < 4; ++k)
  {
    weightedGradient2 += w[k] * g[k].squaredNorm();
  }
  out.dLambda = detail::lagrangeStep(C, weightedGradient2, lambda, p, out.residual);
  for (int k = 0; k < 4; ++k)
  {
    out.dx[k] = w[k] * out.dLambda * g[k];
  }
  return out;
}

/// Attachment of a particle to a fixed target point: C = |x - target| (a zero-length spring to
/// the world). A fixed point is the limit w = 0, which the simulation handles by pinning.
inline Projection<1> projectAttachment(
  const Vec3& x, double w, const Vec3& target, double lambda, const ProjectionParameters& p)
{
  Projection<1> out;
  const Vec3 d = x - target;
  const double C = d.norm();
  if (C <= 0.0)
  {
    return out;
  }
  out.dLambda = detail::lagrangeStep(C, w, lambda, p, out.residual);
  out.dx[0] = w * out.dLambda * (d / C);
  return out;
}

/// Half-space (floor) constraint C = n . (x - origin) - radius >= 0 with unit n. Contacts are
/// hard (no compliance, no PBD stiffness): the particle is moved straight out.
inline Projection<1> projectPlane(
  const Vec3& x, double w, const Vec3& origin, const Vec3& unitNormal, double radius)
{
  Projection<1> out;
  const double C = unitNormal.dot(x - origin) - radius;
  if (C >= 0.0 || w <= 0.0)
  {
    return out;
  }
  out.residual = C;
  out.dLambda = -C;
  out.dx[0] = -C * unitNormal;
  return out;
}

/// PBD's stiffness correction (Mueller et al. 2007, section 3.3): with n projections per step the
/// constraint error after them scales like (1 - k')^n, so k' = 1 - (1 - k)^(1/n) makes the
/// effective stiffness k independent of n. n is the iteration count of the step, fixed for the
/// step; the thesis code used the current iteration index instead, which makes the stiffness
/// vary within a step.
inline double pbdStiffnessPerIteration(double stiffness, int iterations)
{
  if (stiffness >= 1.0 || iterations <= 1)
  {
    return stiffness >= 1.0 ? 1.0 : stiffness;
  }
  return 1.0 - std::pow(1.0 - stiffness, 1.0 / iterations);
}

} // namespace softbody
