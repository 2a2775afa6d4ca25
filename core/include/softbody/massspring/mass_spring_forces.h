// Internal forces of the mass-spring model (see material.h for the equations).
//
// Two passes keep the parallel loops race-free and thread-count independent:
//   1. per element (edge or tet), in parallel: evaluate the element's force magnitude;
//   2. per vertex, in parallel: gather the contributions of the vertex's own edges and tets in
//      the fixed order of the CSR incidence lists.
// No atomics, no per-thread accumulation buffers, identical results for any thread count.
#pragma once

#include "softbody/common/simd.h"
#include "softbody/material/material.h"

#include <vector>

namespace softbody
{

/// Per-element results of pass 1, reused across steps to avoid allocation.
struct ForceScratch
{
  std::vector<Vec3> springForce; ///< force on edge.a (edge.b gets its negative) [N]
  /// Force on corner k of tet t, at 4 t + k: s_t dV/dp_k [N]. Computed in the tet pass, where
  /// the tet's corners are at hand, so the per-vertex gather reads one vector per corner
  /// instead of the tet's indices, three positions and a cross product (on a 180k-tet TetGen
  /// mesh a gather doing that work is 60% of the force evaluation).
  std::vector<Vec3> tetCornerForce;
};

/// Sum of spring and volume forces on every vertex, including their damping terms.
/// `forces` is resized to the vertex count and overwritten. The element passes run four
/// elements at a time (common/simd.h); every SimdLevel gives the same bits.
void computeInternalForces(const Topology& topology, const ElementConstants& constants,
  const std::vector<Vec3>& positions, const std::vector<Vec3>& velocities, ForceScratch& scratch,
  std::vector<Vec3>& forces, SimdLevel level = bestSimdLevel());

/// Elastic potential energy sum_e k_D/2 C_D^2 + sum_t k_V/2 C_V^2 [J] (for tests and checks).
double elasticEnergy(const Topology& topology, const ElementConstants& constants,
  const std::vector<Vec3>& positions);

/// Largest l / l0 over all edges; NaN if any position is not finite.
double maxStretchRatio(const Topology& topology, const ElementConstants& constants,
  const std::vector<Vec3>& positions);

} // namespace softbody
