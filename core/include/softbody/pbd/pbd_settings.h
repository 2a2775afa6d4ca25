// What a PBD/XPBD simulation is told: formulation, solver, step, iterations, materials of each
// constraint type, floor contact, and the plastic and breakable behaviour of links. Immutable
// once the simulation is made.
#pragma once

#include "softbody/common/geometry.h"
#include "softbody/mesh/tet_mesh.h" // InvertedTetPolicy
#include "softbody/scene/scene.h"

namespace softbody
{

enum class PbdFormulation
{
  Pbd, ///< stiffness k in [0, 1] per constraint type, iteration-count corrected
  Xpbd ///< compliance alpha (inverse stiffness, physical units) per constraint type
};

enum class PbdSolver
{
  GaussSeidel, ///< SOR when relaxation != 1
  Jacobi,      ///< averaged Jacobi with relaxation
  ParallelGaussSeidel
};

enum class PbdPrediction
{
  SymplecticEuler, ///< v += h a; p = x + h v
  Verlet           ///< p = x + h v + h^2 a, v the position difference of the last step
};

/// Stiffness (PBD) or compliance (XPBD) of one constraint type.
struct ConstraintMaterial
{
  double stiffness = 1.0;  ///< PBD, in [0, 1]
  double compliance = 0.0; ///< XPBD, >= 0; units: inverse of the constraint's stiffness
  bool operator==(const ConstraintMaterial&) const = default;
};

/// The PBD/XPBD method's settings on top of the scene every method shares.
struct PbdSettings : Scene
{
  PbdFormulation formulation = PbdFormulation::Xpbd;
  PbdSolver solver = PbdSolver::GaussSeidel;
  PbdPrediction prediction = PbdPrediction::SymplecticEuler;
  /// [s]; 0 = automatic: steps of at most kDefaultPbdStep (PBD is stable at any step; the step
  /// sets the accuracy, not the stability).
  double timeStep = 0.0;
  int substeps = 1;   ///< each step runs `substeps` substeps of `iterations` iterations each
  int iterations = 10; ///< per substep; the cap when residualTolerance > 0
  /// Record the residual after each iteration of the last step of every advance() (the
  /// filter's Convergence output). Costs one evaluation pass per iteration of that step only.
  bool reportConvergence = true;
  /// Stop iterating once sqrt(sum of squared residuals) is below this [constraint units]; 0 runs
  /// the fixed count. Checking costs one extra evaluation pass per iteration.
  double residualTolerance = 0.0;
  double relaxation = 1.0; ///< SOR factor (Gauss-Seidel) or Jacobi's relaxation, in (0, 2)
  /// Velocity damping rate [1/s]: v *= max(0, 1 - damping h) each substep.
  double damping = 0.0;

  /// Radius of the particles of particle bodies (points in no tet and no surface triangle:
  /// voxelized lattices), which collide as spheres of it [m].
  double particleRadius = 0.0;

  ConstraintMaterial links;       ///< distance: compliance in m/N
  ConstraintMaterial volumes;     ///< tet volume (C = V - V0 in m^3): compliance in m^3/Pa
  ConstraintMaterial attachments; ///< soft pins: compliance in m/N

  /// XPBD only: the Spring Network's tet edges and volumes take their compliances from the
  /// body's material (Body::material: Young's modulus, Poisson's ratio, per tet or uniform)
  /// as the mass-spring model derives its stiffnesses (k_D = 15 mu V_e, k_V = (lambda - mu) V_t,
  /// material.h), so both methods minimize the same elastic energy; otherwise `links` and
  /// `volumes` give them. A continuum model always takes its tets' deviatoric and hydrostatic
  /// constraints (material/constraint_forms.h) from the material, whatever this says. Explicit
  /// links keep `links.compliance`.
  bool elasticFromMaterial = false;

  /// A link breaks when |l - l0| / l0 (l0 its original rest length) passes this; 0 = unbreakable.
  double breakingStrain = 0.0;
  /// Plastic links: past this strain (relative to the current rest length) the rest length
  /// creeps toward the current length at `plasticCreep` [1/s]; 0 = elastic.
  double plasticYield = 0.0;
  double plasticCreep = 0.0;

  InvertedTetPolicy invertedTets = InvertedTetPolicy::Reorient;
  bool operator==(const PbdSettings&) const = default;
};

constexpr double kDefaultPbdStep = 1.0 / 120.0;

} // namespace softbody
