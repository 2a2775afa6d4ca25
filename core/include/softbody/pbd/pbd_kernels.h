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
#include "softbody/common/simd.h"

#include <array>
#include <cmath>
#include <type_traits>

namespace softbody
{

/// What one projection asks of its N particles. `Multiplier` is double for one constraint, a
/// small Eigen vector for constraints solved together (pbd_tet_elastic_kernel.h).
template <int N, class Multiplier = double>
struct Projection
{
  Projection()
  {
    for (Vec3& v : dx)
    {
      v.setZero(); // Eigen leaves vectors uninitialized
    }
    if constexpr (std::is_arithmetic_v<Multiplier>)
    {
      dLambda = 0.0;
    }
    else
    {
      dLambda.setZero();
    }
  }
  std::array<Vec3, N> dx;   ///< position corrections, already weighted by inverse mass
  Multiplier dLambda;       ///< change of the Lagrange multiplier(s) (XPBD); 0 when inactive
  double residual = 0.0;    ///< C + alphaTilde * lambda before the projection (0 if satisfied;
                            ///< the norm of the vector for constraints solved together)
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

#if defined(__GNUC__) // GCC and Clang
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi" // the lane templates are always inlined (common/simd.h)
#endif
/// The least volume a tet projection keeps, as a fraction of the rest volume (lanes::tetVolume).
constexpr double kLeastVolumeFraction = 0.1;

namespace lanes
{
/// What a distance or volume projection asks of its corners, for one lane (T = double) or
/// four (T = simd::Lanes4). The scalar kernels below and the colored solver's wide kernels
/// (pbd_wide_kernels.h) both run these templates, so they agree bit for bit.
template <class T, int N>
struct ProjectionLanes
{
  simd::Vec3Lanes<T> dx[N]; ///< corrections, weighted by inverse mass [m]
  T dLambda;                ///< change of the multiplier; 0 where inactive
  T residual;               ///< C + alphaTilde lambda before the projection; 0 where inactive
};

/// Distance constraint C = |d| - rest, d = x0 - x1, gradients +-d/|d|. With the XPBD step
/// dLambda = -scale (C + alphaTilde lambda) / (w0 + w1 + alphaTilde), the corrections are
/// dx0 = w0 dLambda d/|d| and dx1 = -w1 dLambda d/|d|, computed as (w p) d with the one
/// division p = -scale (C + alphaTilde lambda) / ((w0 + w1 + alphaTilde) |d|), and dLambda = p |d|
/// (dividing n = d/|d| component by component would take four; the sequential Gauss-Seidel on
/// the 180k-tet ellipsoid takes 2.78-2.84 ms per iteration with one division per link and one
/// per tet, 3.01-3.23 with two each, bench_wide_kernels).
template <class T>
SOFTBODY_SIMD_INLINE ProjectionLanes<T, 2> distance(const simd::Vec3Lanes<T>& x0, const simd::Vec3Lanes<T>& x1,
  T w0, T w1, T rest, bool atLeast, T lambda, T scale, T alphaTilde)
{
  using simd::broadcast;
  const T zero = broadcast<T>(0.0);
  const simd::Vec3Lanes<T> d = x0 - x1;
  const T length = simd::sqrt(simd::dot(d, d));
  const T C = length - rest;
  // Coincident points have no direction to move along; a satisfied AtLeast asks for nothing.
  auto moves = simd::negate(length <= zero);
  if (atLeast)
  {
    moves = simd::both(moves, C < zero);
  }
  const auto stiff = simd::both(moves, scale != zero); // zero stiffness asks for nothing
  const T residual = C + alphaTilde * lambda;
  const T denominator = (w0 + w1) + alphaTilde;
  // Both ends pinned (denominator 0): nothing can move.
  const auto solves = simd::both(stiff, denominator > zero);
  ProjectionLanes<T, 2> out;
  out.residual = simd::select(stiff, residual, zero);
  // One division: the correction per unit length, dLambda / |d|, and dLambda from it.
  const T perLengthAll = (-scale * residual) / (denominator * length);
  const T perLength = simd::select(solves, perLengthAll, zero);
  out.dLambda = simd::select(solves, perLengthAll * length, zero);
  out.dx[0] = (w0 * perLength) * d;
  out.dx[1] = (-(w1 * perLength)) * d;
  return out;
}

/// Tet volume constraint C = V - restVolume with V = e1.(e2 x e3)/6 (e_i = x_i - x0), written
/// with G_k = 6 dV/dx_k (G1 = e2 x e3, G2 = e3 x e1, G3 = e1 x e2, G0 = -(G1 + G2 + G3)):
///   sum_k w_k |g_k|^2 + alphaTilde = (sum_k w_k |G_k|^2 + 36 alphaTilde) / 36
///   q = -scale (C + alphaTilde lambda) / (sum_k w_k |G_k|^2 + 36 alphaTilde)
///   dLambda = 36 q,   dx_k = w_k dLambda g_k = (6 q w_k) G_k.
/// One division per tet: the constraint is evaluated in units of 6 V (6 C = e1.G1 - 6 V0, no
/// division for the volume) and q = -scale 6 (C + alphaTilde lambda) / (6 (sum_k w_k |G_k|^2 +
/// 36 alphaTilde)). Dividing the gradients by 6 would take nine more and the volume one more
/// (the divider's throughput is the kernel's bottleneck: see README, Performance).
///
/// Non-inversion: a tet crushed below kLeastVolumeFraction of its rest volume is projected as
/// the hard inequality V >= kLeastVolumeFraction * restVolume (no compliance, its multiplier
/// left as it is) instead of the compliant equality, where that asks for more. A compliant tet under a load the solve has
/// not yet carried up through the body (a body landing on the floor, whose contacts lift its
/// bottom layer) otherwise flips: with a soft compliance the equality's step is a small
/// fraction of what it would take to undo it.
template <class T>
SOFTBODY_SIMD_INLINE ProjectionLanes<T, 4> tetVolume(const simd::Vec3Lanes<T>& x0, const simd::Vec3Lanes<T>& x1,
  const simd::Vec3Lanes<T>& x2, const simd::Vec3Lanes<T>& x3, const T (&w)[4], T restVolume, T lambda, T scale,
  T alphaTilde)
{
  using simd::broadcast;
  const T zero = broadcast<T>(0.0);
  const simd::Vec3Lanes<T> e1 = x1 - x0, e2 = x2 - x0, e3 = x3 - x0;
  ProjectionLanes<T, 4> out;
  simd::Vec3Lanes<T>(&G)[4] = out.dx; // the gradients, scaled in place into the corrections
  G[1] = simd::cross(e2, e3);
  G[2] = simd::cross(e3, e1);
  G[3] = simd::cross(e1, e2);
  G[0] = -((G[1] + G[2]) + G[3]);
  // In units of 6 V: no division for the volume; the 6 goes into the denominator instead.
  const T six = broadcast<T>(6.0);
  const T volume6 = simd::dot(e1, G[1]);
  const T C6 = volume6 - six * restVolume;
  const T weightedGradient2 = ((w[0] * simd::dot(G[0], G[0]) + w[1] * simd::dot(G[1], G[1])) +
                                w[2] * simd::dot(G[2], G[2])) + w[3] * simd::dot(G[3], G[3]);
  const auto stiff = scale != zero; // zero stiffness asks for nothing
  const T residual6 = C6 + six * (alphaTilde * lambda);
  T demand = -residual6;
  T denominator = six * (weightedGradient2 + broadcast<T>(36.0) * alphaTilde);
  const T shortfall6 = six * (broadcast<T>(kLeastVolumeFraction) * restVolume) - volume6;
  auto hard = shortfall6 > zero;
  if (simd::any(hard)) // rare: a branch skips the selects in every other projection
  {
    // The hard inequality where it asks for more than the equality's step (a stiff tet's own
    // step can): (least - V) / sum w|G|^2 > -residual / equality denominator, cross-multiplied
    // (both denominators positive where anything moves) to keep one division per tet.
    const T hardDenominator = six * weightedGradient2;
    hard = simd::both(hard, shortfall6 * denominator > demand * hardDenominator);
    demand = simd::select(hard, shortfall6, demand);
    denominator = simd::select(hard, hardDenominator, denominator);
  }
  // All corners pinned, or a flat tet (zero gradients): nothing can move.
  const auto solves = simd::both(stiff, denominator > zero);
  const T q = simd::select(solves, (scale * demand) / denominator, zero);
  out.residual = simd::select(stiff, residual6 * broadcast<T>(1.0 / 6.0), zero);
  out.dLambda = simd::select(hard, zero, broadcast<T>(36.0) * q);
  const T sixQ = broadcast<T>(6.0) * q;
  for (int k = 0; k < 4; ++k)
  {
    G[k] = (w[k] * sixQ) * G[k];
  }
  return out;
}

inline simd::Vec3Lanes<double> toLanes(const Vec3& v)
{
  return { v.x(), v.y(), v.z() };
}
inline Vec3 fromLanes(const simd::Vec3Lanes<double>& v)
{
  return Vec3(v.x, v.y, v.z);
}
} // namespace lanes
#if defined(__GNUC__) // GCC and Clang
#pragma GCC diagnostic pop
#endif

/// Distance constraint C = |x0 - x1| - rest; gradients n and -n with n = (x0 - x1) / |x0 - x1|.
inline Projection<2> projectDistance(const Vec3& x0, const Vec3& x1, double w0, double w1,
  double rest, DistanceKind kind, double lambda, const ProjectionParameters& p)
{
  const auto r = lanes::distance<double>(lanes::toLanes(x0), lanes::toLanes(x1), w0, w1, rest,
    kind == DistanceKind::AtLeast, lambda, p.scale, p.alphaTilde);
  Projection<2> out;
  out.dx[0] = lanes::fromLanes(r.dx[0]);
  out.dx[1] = lanes::fromLanes(r.dx[1]);
  out.dLambda = r.dLambda;
  out.residual = r.residual;
  return out;
}

/// Tet volume constraint C = V(x) - restVolume (signed volume, so an inverted tet is pushed back
/// through zero); gradients dV/dx_k as tetVolumeGradients (geometry.h) gives them.
inline Projection<4> projectTetVolume(const std::array<Vec3, 4>& x, const std::array<double, 4>& w,
  double restVolume, double lambda, const ProjectionParameters& p)
{
  const double wl[4] = { w[0], w[1], w[2], w[3] };
  const auto r = lanes::tetVolume<double>(lanes::toLanes(x[0]), lanes::toLanes(x[1]), lanes::toLanes(x[2]),
    lanes::toLanes(x[3]), wl, restVolume, lambda, p.scale, p.alphaTilde);
  Projection<4> out;
  for (int k = 0; k < 4; ++k)
  {
    out.dx[static_cast<std::size_t>(k)] = lanes::fromLanes(r.dx[k]);
  }
  out.dLambda = r.dLambda;
  out.residual = r.residual;
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
