// Everything a mass-spring stepper prepares before its first step, shared by the CPU stepper
// (MassSpringSimulation) and the GPU one (gpu/), so both validate the same way, build the same
// topology, constants and masses, and choose the same step size from the same stability
// estimate. Only the per-step work differs between them.
#pragma once

#include "softbody/common/state.h"
#include "softbody/massspring/mass_spring_settings.h"
#include "softbody/material/mass.h"

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
  ElementConstants constants;
  PointMasses masses;
  double step = 0.0;       ///< step size advance() uses at most [s]
  double stableStep = 0.0; ///< estimated stable step of scene.integrator [s]; 0 if none
  double omegaMax = 0.0;   ///< highest-frequency bound [rad/s]
  std::vector<std::string> warnings;
};

/// Validates and prepares the body; throws InvalidInputError with a user-facing message.
MassSpringSetup prepareMassSpring(BodyDescription body, const SceneSettings& scene);

/// Initial state: rest positions, zero velocities, time 0.
DynamicState restState(const MassSpringSetup& setup);

/// True when the state must be declared diverged: `maxStretch` is the largest l / l0 (NaN if a
/// position is not finite), `finiteVelocities` whether every velocity is finite.
bool hasDiverged(const SceneSettings& scene, double maxStretch, bool finiteVelocities);

/// The user-facing message of the SimulationDivergedError thrown when hasDiverged().
std::string divergenceMessage(const DynamicState& state, double maxStretch,
  bool finiteVelocities, double step, double stableStep);

} // namespace softbody
