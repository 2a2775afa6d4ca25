// The highest natural angular frequency omega_max of a mass-spring body at rest: the square root
// of the largest eigenvalue of M^-1 K, K the stiffness of the springs and volume terms linearized
// at the rest shape,
//   K = sum_springs k_e (n n^T block pattern) + sum_tets k'_t g g^T   (g: the 12 volume gradients),
// (the stretch terms of the tangent vanish at rest, l = l0 and V = V0). It sets every explicit
// integrator's stable step (stability.h), so it must not be under-estimated, and an excess f
// costs a factor f in the step (f^2 where damping over-damps the top modes).
//
// Two estimates, the set-up takes the smaller (the second with a margin for deformation):
// * gershgorinFrequencyBound: a rigorous upper bound (block Gershgorin), cheap, but 2-2.7x high
//   on regular meshes where a vertex's neighbours do not all push against it at once.
// * lanczosFrequencyEstimate: a fixed number of Lanczos steps on the symmetric form
//   M^-1/2 K M^-1/2 (matrix-free, one gather per product), from a fixed pseudo-random start,
//   giving the top Ritz value theta plus its residual norm |beta_m s_m|: some eigenvalue lies
//   within that residual of theta (Parlett, The Symmetric Eigenvalue Problem, 11-5), and theta
//   is never above lambda_max, so theta + residual is an upper estimate of lambda_max whenever the
//   top Ritz value approximates the top eigenvalue (not a proof: a start vector orthogonal to the
//   top modes would miss them; a pseudo-random one does not, in exact arithmetic, with
//   probability 1). Deterministic: fixed seed and iteration count, sums in fixed order.
#pragma once

#include "softbody/material/material.h"
#include "softbody/mesh/topology.h"

#include <functional>
#include <vector>

namespace softbody
{

/// Block Gershgorin upper bound of omega_max [rad/s]: max_i w_i * (sum over i's springs of 2 k +
/// sum over i's tets of k' |g_i| sum_j |g_j|).
double gershgorinFrequencyBound(const Topology& topology, const ElementConstants& constants,
  const std::vector<double>& inverseMass, const std::vector<Vec3>& restPositions);

/// Result of the Lanczos iteration on M^-1 K at rest.
struct LanczosFrequency
{
  double ritzOmega = 0.0;  ///< sqrt of the top Ritz value [rad/s]: a lower bound of omega_max
  double upperOmega = 0.0; ///< sqrt(theta + residual) [rad/s]: the upper estimate
  int iterations = 0;      ///< Lanczos steps taken (fewer than asked when the space is exhausted)
  // Both 0 when no estimate was made: no free point, or the tridiagonal eigensolver failed.
};

/// `iterations` Lanczos steps (matrix-free products K x over springs and tets, gathered per
/// vertex; pinned points, w_i = 0, take no part).
LanczosFrequency lanczosFrequencyEstimate(const Topology& topology,
  const ElementConstants& constants, const std::vector<double>& inverseMass,
  const std::vector<Vec3>& restPositions, int iterations);

/// y = M^-1/2 K M^-1/2 x for some rest stiffness K: the operator the iteration runs on. It
/// must be the same bit for bit at any thread count (sums in a fixed order) for the estimate
/// to be.
using ScaledRestProduct = std::function<void(const std::vector<Vec3>& x, std::vector<Vec3>& y)>;

/// The same iteration on any body's scaled rest stiffness (the continuum models',
/// element_frequency.h), from the same start vector.
LanczosFrequency lanczosFrequencyEstimate(const ScaledRestProduct& product,
  const std::vector<double>& inverseMass, const std::vector<Vec3>& restPositions, int iterations);

/// Lanczos steps the set-up uses: the top Ritz value of the public meshes (slivers included) is
/// within a few percent of omega_max by then, and the cost is that many force evaluations.
inline constexpr int kFrequencyLanczosSteps = 40;

/// Factor on the rest-state Lanczos estimate. Both estimates are of the body at rest, but a
/// deformed body is stiffer: a spring stretched by a strain s adds k s across itself, a tet
/// squeezed or swollen adds k' (V - V0) d2V/dp2, so the top frequency grows with the strain.
/// 1.2 covers 44% more stiffness. And a step right at the linear limit leaves the top modes
/// barely damped (|amplification| near 1): on the floor, Midpoint's resting box
/// (Simulation.BodyFallsAndComesToRestOnTheFloor) keeps points moving at 0.069 m/s (2.5 g h) with
/// 0.9 of the unmargined limit, 0.048 m/s with this margin, 0.028 m/s (1.5 g h) at 0.6.
inline constexpr double kDeformationMargin = 1.2;

/// The set-up's omega_max [rad/s]: min(Gershgorin bound, kDeformationMargin x Lanczos upper
/// estimate).
double highestFrequencyBound(const Topology& topology, const ElementConstants& constants,
  const std::vector<double>& inverseMass, const std::vector<Vec3>& restPositions);

} // namespace softbody
