/**
 * @file   vtkSoftBodySimulationFactory.h
 * @brief  Builds the simulation the Soft Body filter's settings ask for: Mass-Spring on the CPU
 *         or on the GPU (falling back to the CPU, with the reason, when the GPU cannot run it),
 *         or PBD/XPBD; every one on the body renumbered for locality, outputs in the input's
 *         order.
 */
#ifndef vtkSoftBodySimulationFactory_h
#define vtkSoftBodySimulationFactory_h

#include "vtkSoftBodyParameters.h"
#include "vtkSoftBodyPbdAdapter.h"

#include "softbody/common/simulation.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

struct vtkSoftBodyCoreSettings;
class vtkUnstructuredGrid;

/// A simulation as built, and what the filter reports about how it runs.
struct vtkSoftBodyBuiltSimulation
{
  std::unique_ptr<softbody::Simulation> Simulation;
  /// Set when the simulation is PBD/XPBD: the solver inside `Simulation` (which maps its
  /// particles back to the input's order); its tet and link indices are the input's.
  softbody::PbdSimulation* Pbd = nullptr;
  vtkSoftBodyPbdAdapter PbdAdapter;
  /// The device the simulation runs on (may differ from the Device property after a fallback).
  int DeviceUsed = vtkSoftBodyParameters::DEVICE_CPU;
  std::string GLRenderer;    ///< the GPU's renderer; empty on the CPU
  std::string DeviceWarning; ///< why the GPU was not used although asked for; empty otherwise
  /// What the factory itself said of the input (its units), for the Warnings field data: the
  /// simulation's own warnings do not hold them.
  std::vector<std::string> InputWarnings;
};

namespace vtkSoftBodySimulationFactory
{
/// Called with each warning as it arises (the filter prints it).
using WarningSink = std::function<void(const std::string&)>;

/// Builds the simulation for `settings` from `input` into `built`. `withObstacles` (an
/// Obstacles input is connected) or body collisions keep Mass-Spring on the CPU: the GPU
/// stepper collides with the floor only. Returns false with `error` set for input the filter
/// refuses; throws softbody::InvalidInputError for what core refuses.
bool Build(vtkUnstructuredGrid* input, const vtkSoftBodyCoreSettings& settings,
  bool withObstacles, const WarningSink& warn, vtkSoftBodyBuiltSimulation& built,
  std::string& error);
}

#endif
