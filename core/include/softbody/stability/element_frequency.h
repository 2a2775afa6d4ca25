// The highest natural angular frequency of a body written as element families
// (material/element_model.h): the block Gershgorin bound from each family's stiffnessBound,
//   omega_max^2 <= max_i w_i sum over i's element corners of stiffnessBound,
// rigorous at rest (highest_frequency.h explains why the network's set-up sharpens its own with
// Lanczos; the continuum models take this bound, which costs them a smaller step, not safety).
#pragma once

#include "softbody/material/tet_elasticity.h"

#include <vector>

namespace softbody
{

/// Gershgorin bound of omega_max [rad/s] of a continuum body at rest.
double continuumFrequencyBound(const Topology& topology, const TetElasticConstants& constants,
  const std::vector<double>& inverseMass, const std::vector<Vec3>& restPositions);

} // namespace softbody
