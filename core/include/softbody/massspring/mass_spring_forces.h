// Internal forces of the mass-spring model (see material.h for the equations).
//
// Two passes keep the parallel loops race-free and thread-count independent:
//   1. per element (edge or tet), in parallel: evaluate the element's force magnitude;
//   2. per vertex, in parallel: gather the contributions of the vertex's own edges and tets in
//      the fixed order of the CSR incidence lists.
// No atomics, no per-thread accumulation buffers, identical results for any thread count.
#pragma once

#include "softbody/material/material.h"

#include <vector>

namespace softbody
{

/// Per-element results of pass 1, reused across steps to avoid allocation.
struct ForceScratch
{
  std::vector<Vec3> springForce; ///< force on edge.a (edge.b gets its negative) [N]
  std::vector<double> tetScale;  ///< force on corner i is tetScale * dV/dp_i [N/m^2]
};

/// Sum of spring and volume forces on every vertex, including their damping terms.
/// `forces` is resized to the vertex count and overwritten.
void computeInternalForces(const Topology& topology, const ElementConstants& constants,
  const std::vector<Vec3>& positions, const std::vector<Vec3>& velocities, ForceScratch& scratch,
  std::vector<Vec3>& forces);

/// Elastic potential energy sum_e k_D/2 C_D^2 + sum_t k_V/2 C_V^2 [J] (for tests and checks).
double elasticEnergy(const Topology& topology, const ElementConstants& constants,
  const std::vector<Vec3>& positions);

/// Largest l / l0 over all edges; NaN if any position is not finite.
double maxStretchRatio(const Topology& topology, const ElementConstants& constants,
  const std::vector<Vec3>& positions);

} // namespace softbody
