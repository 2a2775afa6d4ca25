// Whether a body can carry its own weight. A column of height H standing on its base (or hung
// from its top) is strained at the support by its weight as rho g H / E: at 1 the weight alone
// asks for more than the material gives at any strain, so the body collapses into itself (or
// stretches without end) under gravity whatever the integrator and its step. A mesh in
// millimetres read as metres (1000x too tall) or a YoungsModulus typed in kPa are the usual
// causes. The set-up warns of it, and a run that then blows up says this, not "reduce the step".
#pragma once

#include "softbody/common/geometry.h"
#include "softbody/material/material.h"
#include "softbody/mesh/tet_mesh.h"

#include <string>
#include <vector>

namespace softbody
{

struct SelfWeight
{
  double strain = 0.0;  ///< rho g H / E of the worst connected body (0: no gravity or E)
  double height = 0.0;  ///< its extent H along gravity [m]
  double density = 0.0; ///< its volume-weighted density [kg/m^3]
  double youngsModulus = 0.0; ///< its volume-weighted Young's modulus [Pa]
};

/// The self-weight strain of the most strained connected body of `mesh` under `gravity`, from
/// each body's extent along gravity and its volume-weighted density and Young's modulus.
/// Zero for the spring network's Raw constants, which have no E.
SelfWeight selfWeightStrain(const TetMesh& mesh, const std::vector<double>& restVolume,
  const MaterialSettings& material, const Vec3& gravity);

/// At or above this strain a supported body cannot carry its own weight.
constexpr double kCollapsingSelfWeightStrain = 1.0;

/// The set-up's warning for a supported body that cannot carry its weight; empty below
/// kCollapsingSelfWeightStrain.
std::string selfWeightWarning(const SelfWeight& weight);

} // namespace softbody
