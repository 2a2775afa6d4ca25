// The highest natural angular frequency of a continuum (finite-element) body at rest, as the
// network's is estimated (highest_frequency.h): two estimates, the set-up takes the smaller.
// * continuumGershgorinBound: the block Gershgorin bound from each element family's
//   stiffnessBound, omega_max^2 <= max_i w_i sum over i's element corners of stiffnessBound;
//   rigorous at rest, and 1.4-2x high on real meshes, which costs the explicit integrators
//   that factor in their step.
// * the Lanczos upper estimate on M^-1/2 K M^-1/2, K the rest stiffness every continuum law
//   shares: linear elasticity with the typed E and nu (Corotated and Stable Neo-Hookean both
//   linearize to it at F = I), K u per tet = V0 (2 mu eps + lambda tr(eps) I) g_c with
//   eps = sym(sum_c u_c g_c^T); times kDeformationMargin for a deformed body's extra stiffness.
#pragma once

#include "softbody/material/tet_elasticity.h"
#include "softbody/stability/highest_frequency.h"

#include <vector>

namespace softbody
{

/// Block Gershgorin bound of omega_max [rad/s] of a continuum body at rest.
double continuumGershgorinBound(const Topology& topology, const TetElasticConstants& constants,
  const std::vector<double>& inverseMass, const std::vector<Vec3>& restPositions);

/// `iterations` Lanczos steps on the continuum body's scaled rest stiffness.
LanczosFrequency continuumLanczosEstimate(const Topology& topology, const TetElasticConstants& constants,
  const std::vector<double>& inverseMass, const std::vector<Vec3>& restPositions, int iterations);

/// The set-up's omega_max [rad/s]: min(Gershgorin bound, kDeformationMargin x Lanczos upper
/// estimate), as highestFrequencyBound is for the network.
double continuumFrequencyBound(const Topology& topology, const TetElasticConstants& constants,
  const std::vector<double>& inverseMass, const std::vector<Vec3>& restPositions);

/// The body's omega_max [rad/s] for its model: continuumFrequencyBound for the finite-element
/// models (`tets` their constants), highestFrequencyBound for the spring network. The set-up's
/// step and Mesh Quality's report both come from here, so they agree.
double modelFrequencyBound(MaterialModel model, const Topology& topology, const ElementConstants& network,
  const TetElasticConstants& tets, const std::vector<double>& inverseMass, const std::vector<Vec3>& restPositions);

} // namespace softbody
