// Everything a mass-spring stepper prepares before its first step, shared by the CPU stepper
// (MassSpringSimulation) and the GPU one (gpu/), so both validate the same way, build the same
// topology, constants and masses, and choose the same step size from the same stability
// estimate. Only the per-step work differs between them.
#pragma once

#include "softbody/common/state.h"
#include "softbody/massspring/mass_spring_settings.h"
#include "softbody/material/mass.h"
#include "softbody/material/self_weight.h"
#include "softbody/material/tet_elasticity.h"
#include "softbody/scene/boundary_conditions.h"

#include <string>
#include <vector>

namespace softbody
{

/// The prepared, immutable part of a mass-spring body.
struct MassSpringSetup
{
  SceneSettings scene; ///< as given, with the floor normal normalized
  TetMesh mesh;        ///< validated; inverted tets re-oriented per scene.invertedTets
  Topology topology;
  MaterialModel model = MaterialModel::SpringNetwork;
  /// The spring network's constants; for a continuum model only its geometry and damping time.
  ElementConstants constants;
  TetElasticConstants tetConstants; ///< the continuum models' (empty for the network)
  PointMasses masses; ///< inverse mass 0 at pinned points and points whose x, y, z are held
  BoundaryConditions conditions;
  double step = 0.0;       ///< step size advance() uses at most [s]
  double stableStep = 0.0; ///< estimated stable step of scene.integrator [s]; 0 if none
  double omegaMax = 0.0;   ///< highest-frequency bound [rad/s]
  /// Stable step of the same integrator without damping (Euler-Cromer's for Euler) [s]: when it
  /// is much larger than stableStep, damping, not stiffness, limits the step.
  double undampedStableStep = 0.0;
  /// Whether the body can carry its own weight (warned of when it is held and cannot); a
  /// blow-up's message names it.
  SelfWeight selfWeight;
  std::vector<std::string> warnings;
};

/// Validates and prepares the body; throws InvalidInputError with a user-facing message.
MassSpringSetup prepareMassSpring(Body body, const SceneSettings& scene);

/// Initial state: rest positions, zero velocities, time 0.
DynamicState restState(const MassSpringSetup& setup);

/// A mass-spring step costs about this many tet-steps per second and thread on this project's
/// 2-core machine (bench_mass_spring: 2.4e7 to 3.1e7); used only to say ahead of a run that it
/// will take long.
constexpr double kTetStepsPerSecond = 3.0e7;

/// What the cost of a run depends on, kept by the steppers.
struct StepCost
{
  double step = 0.0;               ///< [s]
  double stableStep = 0.0;         ///< [s]
  double undampedStableStep = 0.0; ///< [s]
  double maxDampingTime = 0.0;     ///< [s]
  Integrator integrator = Integrator::EulerCromer;
  std::size_t tetCount = 0;
};
StepCost stepCostOf(const MassSpringSetup& setup);

/// Before a run of `duration` simulated seconds: a warning with the step count, the estimated
/// wall time and the remedies when it needs more than a million steps or about a minute; empty
/// otherwise.
std::string longRunWarning(const StepCost& cost, double duration);

/// True when the state must be declared diverged: `maxStretch` is the largest l / l0 (NaN if a
/// position is not finite), `finiteVelocities` whether every velocity is finite.
bool hasDiverged(const SceneSettings& scene, double maxStretch, bool finiteVelocities);

/// The user-facing message of the SimulationDivergedError thrown when hasDiverged().
/// A body that cannot carry its own weight (selfWeight) is told so, since no step would help.
std::string divergenceMessage(const DynamicState& state, double maxStretch,
  bool finiteVelocities, double step, double stableStep, const SelfWeight& selfWeight);

} // namespace softbody
