// The mass-spring stepper on the GPU: OpenGL 4.3 compute shaders on a headless EGL context.
//
// Same contract and semantics as softbody::MassSpringSimulation: the set-up (validation,
// topology, constants, masses, stability estimate and step choice) is core's own
// (mass_spring_setup.h); only the per-step work runs on the GPU, in core's stage order, in
// double precision, as gather loops over core's CSR incidence lists (deterministic, no
// atomics). The state stays on the GPU between steps and is downloaded only when state() is
// asked for; restoreState() uploads.
//
// All GL work runs on the process's one GL thread, whose context every GPU simulation shares
// (see shared_gl_context.h); the public methods post jobs to it and wait. Like the CPU
// stepper, one simulation is used from one thread at a time.
#pragma once

#include "softbody/massspring/mass_spring_simulation.h" // Body, SceneSettings
#include "softbody/common/simulation.h"

#include <memory>
#include <string>
#include <vector>

namespace softbody::gpu
{

class MassSpringDevice;
class SharedGlContext;
/// What the divergence check needs, reduced on the GPU.
struct DivergenceProbe
{
  double maxStretch = 0.0; ///< largest l / l0; NaN if some length was not finite
  bool finiteVelocities = true;
};

class MassSpringGpuSimulation final : public Simulation
{
public:
  /// Throws InvalidInputError for a body or settings core refuses (same messages as the CPU
  /// stepper) and GpuUnavailableError when no suitable GPU context can be made.
  MassSpringGpuSimulation(const Body& body, const SceneSettings& scene);
  ~MassSpringGpuSimulation() override;
  MassSpringGpuSimulation(const MassSpringGpuSimulation&) = delete;
  MassSpringGpuSimulation& operator=(const MassSpringGpuSimulation&) = delete;

  AdvanceStatus advance(double endTime, const ProgressCallback& progress = {}) override;
  /// Downloads positions and velocities when the GPU is ahead of the host copy.
  const DynamicState& state() const override;
  void restoreState(const DynamicState& snapshot) override;

  const std::vector<Vec3>& restPositions() const override;
  const std::vector<double>& inverseMasses() const override;
  double totalMass() const override;
  std::vector<double> tetVolumeRatios() const override;
  double elasticEnergy() const override; ///< the body's material's, from the downloaded positions
  TetStressField stressField() const override; ///< the continuum's tets; empty for the network
  /// The supports' reactions, from the internal forces the host computes at the downloaded
  /// state (core's code: only for output frames).
  ConditionReadout conditionReadout() const override;
  /// New values for the same conditions (a widget moved while the animation plays); false,
  /// as on the CPU, when their structure differs.
  bool setConditionValues(const std::vector<Condition>& conditions) override;
  double stepSize() const override;
  double estimatedStableStep() const override;
  const std::vector<std::string>& warnings() const override;
  /// Core's mass-spring plan timed on the GPU (GL_TIME_ELAPSED), plus the host<->GPU transfers.
  const StepPlan& stepPlan() const override;
  std::string longRunWarning(double duration) const override;

  const std::string& glRenderer() const { return Renderer; } ///< GL_RENDERER of the context
  const std::string& glVersion() const { return Version; }   ///< GL_VERSION of the context

private:
  struct Prepared;
  void checkDivergence(double maxStretch, bool finiteVelocities) const;

  std::unique_ptr<Prepared> Host; // core's set-up: host-side, immutable but for condition values
  mutable DynamicState State;     // host copy; positions/velocities stale when HostStale
  mutable bool HostStale = false;
  DivergenceProbe LastProbe; // of the last batch of steps
  mutable double TransferSeconds = 0.0;
  std::string Renderer;
  std::string Version;
  // The shared GL thread and context; Device is created, used and destroyed only in its jobs.
  std::shared_ptr<SharedGlContext> Gl;
  std::unique_ptr<MassSpringDevice> Device;
};

/// The GPU stepper, or null with the reason in `whyNot` when no GPU context is available
/// (no EGL vendor or device, no OpenGL 4.3, ...). Invalid input still throws
/// InvalidInputError, as the CPU stepper would.
std::unique_ptr<MassSpringGpuSimulation> tryCreateGpuMassSpring(
  const Body& body, const SceneSettings& scene, std::string& whyNot);

} // namespace softbody::gpu
