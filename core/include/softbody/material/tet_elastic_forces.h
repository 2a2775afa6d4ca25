// What the explicit integrators and the outputs need of a continuum body (tet_elasticity.h):
// its internal forces, its elastic energy, and per tet the strain and stress an engineer reads.
// Forces are gathered per point in Topology::vertexTetCorners' order, so they do not depend on
// the thread count.
#pragma once

#include "softbody/common/tet_stress_field.h"
#include "softbody/material/tet_elasticity.h"

#include <array>
#include <vector>

namespace softbody
{

struct TetElasticScratch
{
  std::vector<std::array<Vec3, 4>> cornerForces;
  NodalPressureField nodal; ///< with the nodal pressure: at the last forces' positions
};

/// Elastic plus viscous forces on every point [N] (f = -dE/dx - the viscous stress's).
void computeTetElasticForces(const Topology& topology, const TetElasticConstants& constants,
  const std::vector<Vec3>& x, const std::vector<Vec3>& v, TetElasticScratch& scratch,
  std::vector<Vec3>& forces);

/// Elastic energy sum_t V0 Psi(F_t) [J] (with the nodal pressure: the tets' part plus the
/// points').
double tetElasticEnergy(const Topology& topology, const TetElasticConstants& constants,
  const std::vector<Vec3>& x);

/// The stress field of a continuum body at positions x. With the nodal pressure, each tet's
/// stress holds its share of the points' pressure and its energy density the mean of its
/// corners' volumetric energy densities.
TetStressField tetStressField(const Topology& topology, const TetElasticConstants& constants,
  const std::vector<Vec3>& x);

} // namespace softbody
