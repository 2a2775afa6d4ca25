// Strain limiting: a position correction applied after each mass-spring integration step.
#pragma once

#include "softbody/material/material.h"

#include <vector>

namespace softbody
{

/// Strain limiting (Provot 1995): springs longer than maxStretch * l0 are shortened back to
/// that length by moving both ends along the spring, in proportion to their inverse masses.
/// Parallel Jacobi iterations in gather form: each vertex moves by the mean of the corrections
/// its violated springs ask of it, so the result does not depend on the number of threads.
/// When `adjustVelocities`, v += dx / h for each moved point (the implicit velocity of
/// position-based integrators such as Verlet). Returns the number of springs found violated
/// in the first iteration.
struct StrainLimitScratch
{
  std::vector<Vec3> edgeCorrection; ///< correction for edge.a (edge.b gets -w_b/w_a of it)
};
std::size_t limitStrain(const Topology& topology, const ElementConstants& constants,
  const std::vector<double>& inverseMass, double maxStretch, int iterations,
  bool adjustVelocities, double h, std::vector<Vec3>& positions, std::vector<Vec3>& velocities,
  StrainLimitScratch& scratch);

} // namespace softbody
