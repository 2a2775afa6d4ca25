#include "vtkSoftBodySimulationFactory.h"

#include "vtkSoftBodyInitialState.h"
#include "vtkSoftBodyInputConversion.h"
#include "vtkSoftBodySettings.h"

#include "vtkUnstructuredGrid.h"

#include "softbody/massspring/mass_spring_reordered.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/reorder.h"
#ifdef SOFTBODY_WITH_GPU
#include "softbody/gpu/mass_spring_gpu_simulation.h"
#endif

#include <sstream>
#include <utility>

namespace
{
/// Bodies outside these sizes [m] are warned about as probably in other length units.
constexpr double kLargestLikelySize = 10.0;
constexpr double kSmallestLikelySize = 1e-3;

/// The GPU mass-spring stepper, or null with the reason why not (then the caller falls back
/// to the CPU). Invalid input throws InvalidInputError as the CPU stepper would.
std::unique_ptr<softbody::Simulation> MakeGpuSimulation(const softbody::Body& body,
  const softbody::SceneSettings& scene, std::string& renderer, std::string& whyNot)
{
#ifdef SOFTBODY_WITH_GPU
  // Built on the body renumbered for locality, like the CPU stepper (mass_spring_reordered.h).
  return softbody::buildReorderedMassSpring(body, scene, softbody::kDefaultVertexOrdering,
    [&](softbody::Body stored) -> std::unique_ptr<softbody::Simulation> {
      std::unique_ptr<softbody::gpu::MassSpringGpuSimulation> simulation =
        softbody::gpu::tryCreateGpuMassSpring(stored, scene, whyNot);
      if (simulation)
      {
        renderer = simulation->glRenderer();
      }
      return simulation;
    });
#else
  (void)body;
  (void)scene;
  (void)renderer;
  whyNot = "this build of the plugin has no GPU backend (SOFTBODY_ENABLE_GPU was off).";
  return nullptr;
#endif
}

/// Mass-Spring on the device asked for, or on the CPU when the GPU cannot run it (the reason
/// goes to DeviceWarning and to `warn`).
bool BuildMassSpring(vtkUnstructuredGrid* input, const vtkSoftBodyCoreSettings& settings,
  bool withObstacles, const vtkSoftBodySimulationFactory::WarningSink& warn,
  vtkSoftBodyBuiltSimulation& built, std::string& error)
{
  softbody::Body body;
  error = vtkSoftBodyInputConversion::Convert(input, settings.PinnedPointsArray, body);
  if (!error.empty())
  {
    return false;
  }
  body.material = settings.Material;
  body.conditions = settings.Conditions;
  error = vtkSoftBodyInputConversion::ConvertCellMaterial(input, settings.YoungsModulusArray,
    settings.PoissonRatioArray, settings.DensityArray, body.material.cells);
  if (!error.empty())
  {
    return false;
  }

  // Throws InvalidInputError for bad geometry or material; the caller reports it.
  // The GPU stepper collides with the floor only (like the implicit integrators' fallback,
  // the CPU runs what the GPU cannot, and says so).
  if (settings.Device == vtkSoftBodyParameters::DEVICE_GPU_EGL &&
    (withObstacles || settings.SelectedScene().collisions.bodiesCollide()))
  {
    built.DeviceWarning = std::string("Device GPU (EGL) collides with the floor only, simulating "
                                      "on the CPU: ") +
      (withObstacles ? "an Obstacles input is connected" : "Collisions includes bodies") +
      " (set Collisions to Obstacles and disconnect the Obstacles to run on the GPU).";
    warn(built.DeviceWarning);
  }
  else if (settings.Device == vtkSoftBodyParameters::DEVICE_GPU_EGL)
  {
    std::string whyNot;
    built.Simulation = MakeGpuSimulation(body, settings.Scene, built.GLRenderer, whyNot);
    if (built.Simulation)
    {
      built.DeviceUsed = vtkSoftBodyParameters::DEVICE_GPU_EGL;
    }
    else
    {
      built.DeviceWarning = "Device GPU (EGL) is unavailable, simulating on the CPU: " + whyNot;
      warn(built.DeviceWarning);
    }
  }
  if (!built.Simulation)
  {
    // Vertices renumbered along a space-filling curve, outputs in the input's order.
    built.Simulation = softbody::makeMassSpringSimulation(std::move(body), settings.Scene);
  }
  return true;
}
} // namespace

//------------------------------------------------------------------------------
bool vtkSoftBodySimulationFactory::Build(vtkUnstructuredGrid* input,
  const vtkSoftBodyCoreSettings& settings, bool withObstacles, const WarningSink& warn,
  vtkSoftBodyBuiltSimulation& built, std::string& error)
{
  const bool made = settings.Method == vtkSoftBodyParameters::PBD ||
      settings.Method == vtkSoftBodyParameters::XPBD
    ? (built.Simulation = built.PbdAdapter.Create(settings, input, error, built.Pbd)) != nullptr
    : BuildMassSpring(input, settings, withObstacles, warn, built, error);
  if (!made)
  {
    return false;
  }
  // Lengths are meters: a body over ten meters (or under a millimeter) across was most likely
  // saved in other units (a 30 cm part in centimeters is 30 "m"), and every density, modulus and
  // the gravity then mean something else. A warning, not a refusal: large soft bodies exist.
  const double size = input->GetLength();
  if (size > kLargestLikelySize || (size > 0.0 && size < kSmallestLikelySize))
  {
    std::ostringstream message;
    message << "The body is " << size << " m across (its bounding-box diagonal): lengths are taken "
            << "as meters. ";
    if (size > kLargestLikelySize)
    {
      message << "If its coordinates are in millimeters (" << size * 1e-3 << " m across), scale it by "
              << "0.001 first; if in centimeters (" << size * 1e-2 << " m), by 0.01 (Filters > "
              << "Transform, Scale).";
    }
    else
    {
      message << "If its coordinates are in kilometers (" << size * 1e3 << " m across), scale it by "
              << "1000 first (Filters > Transform, Scale).";
    }
    built.InputWarnings.push_back(message.str());
    warn(message.str());
  }
  error = vtkSoftBodyInitialState::Apply(input, settings.Initial, *built.Simulation);
  return error.empty();
}
