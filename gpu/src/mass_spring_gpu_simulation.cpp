#include "softbody/gpu/mass_spring_gpu_simulation.h"

#include "mass_spring_device.h"
#include "shared_gl_context.h"

#include "softbody/common/errors.h"
#include "softbody/gpu/gpu_errors.h"
#include "softbody/massspring/mass_spring_setup.h"

#include <chrono>

namespace softbody::gpu
{

struct MassSpringGpuSimulation::Prepared
{
  MassSpringSetup setup;
};

namespace
{

double secondsSince(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

} // namespace

MassSpringGpuSimulation::MassSpringGpuSimulation(const BodyDescription& body, const SceneSettings& scene)
  : Body(std::make_unique<Prepared>(Prepared{ prepareMassSpring(body, scene) }))
  , State(restState(Body->setup))
{
  Gl = SharedGlContext::acquire(); // throws GpuUnavailableError where no context can be made
  try
  {
    Gl->run([this] {
      Device = std::make_unique<MassSpringDevice>(Body->setup);
      Device->uploadState(State.positions, State.velocities);
    });
  }
  catch (...)
  {
    Gl->dispose(Device); // GL objects die on the thread that owns their context
    throw;
  }
  Renderer = Gl->renderer();
  Version = Gl->version();
}

MassSpringGpuSimulation::~MassSpringGpuSimulation()
{
  Gl->dispose(Device);
  // Gl goes with the members: the last simulation to go closes the shared context.
}

const DynamicState& MassSpringGpuSimulation::state() const
{
  if (HostStale)
  {
    const auto start = std::chrono::steady_clock::now();
    Gl->run([this] { Device->downloadState(State.positions, State.velocities); });
    HostStale = false;
    TransferSeconds += secondsSince(start);
  }
  return State;
}

void MassSpringGpuSimulation::restoreState(const DynamicState& snapshot)
{
  if (snapshot.positions.size() != State.positions.size() ||
    snapshot.velocities.size() != State.velocities.size())
  {
    throw InvalidInputError("The snapshot does not belong to this simulation.");
  }
  const auto start = std::chrono::steady_clock::now();
  State = snapshot;
  Gl->run([this] { Device->uploadState(State.positions, State.velocities); });
  HostStale = false;
  TransferSeconds += secondsSince(start);
}

void MassSpringGpuSimulation::checkDivergence(double maxStretch, bool finiteVelocities) const
{
  if (hasDiverged(Body->setup.scene, maxStretch, finiteVelocities))
  {
    const DynamicState& current = state(); // the message names the time; the state is kept
    throw SimulationDivergedError(divergenceMessage(current, maxStretch, finiteVelocities,
                                    Body->setup.step, Body->setup.stableStep),
      current.time);
  }
}

AdvanceStatus MassSpringGpuSimulation::advance(double endTime, const ProgressCallback& progress)
{
  const StepSplit split = splitInterval(endTime - State.time, Body->setup.step);
  if (split.count == 0)
  {
    return AdvanceStatus::Completed;
  }
  const double h = split.size;
  const double startTime = State.time;
  // Steps run in batches that end where core checks for divergence and reports progress
  // (every kDivergenceCheckInterval steps and at the last one): one job and one small
  // read-back per batch instead of a round trip per step.
  unsigned long long done = 0;
  while (done < split.count)
  {
    const unsigned long long batchEnd =
      std::min(split.count, (done / kDivergenceCheckInterval + 1) * kDivergenceCheckInterval);
    const unsigned long long batch = batchEnd - done;
    // Verlet kicks by the mean of the previous and current step (core: integrateStep).
    const double firstKick = 0.5 * (State.previousStep + h);
    const double laterKick = 0.5 * (h + h);
    const DivergenceProbe probe = Gl->run([&] {
      for (unsigned long long s = 0; s < batch; ++s)
      {
        Device->step(h, s == 0 ? firstKick : laterKick);
      }
      return Device->probeDivergence();
    });
    done = batchEnd;
    HostStale = true;
    State.stepCount += batch;
    State.previousStep = h;
    // Accumulating h would drift; the step index gives the time exactly.
    State.time = (done == split.count) ? endTime : startTime + static_cast<double>(done) * h;
    checkDivergence(probe.maxStretch, probe.finiteVelocities);
    if (progress && !progress(double(done) / double(split.count)))
    {
      return AdvanceStatus::Aborted;
    }
  }
  return AdvanceStatus::Completed;
}

const std::vector<Vec3>& MassSpringGpuSimulation::restPositions() const
{
  return Body->setup.mesh.points;
}

const std::vector<double>& MassSpringGpuSimulation::inverseMasses() const
{
  return Body->setup.masses.inverseMass;
}

double MassSpringGpuSimulation::totalMass() const
{
  return Body->setup.masses.totalMass;
}

std::vector<double> MassSpringGpuSimulation::tetVolumeRatios() const
{
  // Only for output frames: computed on the host from the downloaded positions.
  const std::vector<Vec3>& x = state().positions;
  const MassSpringSetup& s = Body->setup;
  std::vector<double> ratios(s.topology.tets.size());
  for (std::size_t t = 0; t < ratios.size(); ++t)
  {
    const Tet& tet = s.topology.tets[t];
    ratios[t] = signedTetVolume(x[tet[0]], x[tet[1]], x[tet[2]], x[tet[3]]) / s.constants.restVolume[t];
  }
  return ratios;
}

double MassSpringGpuSimulation::stepSize() const
{
  return Body->setup.step;
}

double MassSpringGpuSimulation::estimatedStableStep() const
{
  return Body->setup.stableStep;
}

const std::vector<std::string>& MassSpringGpuSimulation::warnings() const
{
  return Body->setup.warnings;
}

std::vector<StageTiming> MassSpringGpuSimulation::stageTimings() const
{
  const std::vector<double> seconds = Gl->run([this] { return Device->stageSeconds(); });
  const MassSpringSetup& s = Body->setup;
  // The stages core's MassSpringSimulation reports, under the same names.
  std::vector<StageTiming> timings;
  timings.push_back({ s.constants.hasVolumeTerm ? "forces: springs + volumes" : "forces: springs",
    seconds[kStageForces] });
  timings.push_back({ std::string("integrate: ") + integratorName(s.scene.integrator),
    seconds[kStageIntegrate] });
  if (s.scene.strainLimit > 0.0)
  {
    timings.push_back({ "strain limit", seconds[kStageStrainLimit] });
  }
  if (s.scene.floorEnabled)
  {
    timings.push_back({ "floor", seconds[kStageFloor] });
  }
  timings.push_back({ "divergence check", seconds[kStageDivergenceCheck] });
  timings.push_back({ "transfers: host <-> GPU", TransferSeconds });
  return timings;
}

std::unique_ptr<MassSpringGpuSimulation> tryCreateGpuMassSpring(
  const BodyDescription& body, const SceneSettings& scene, std::string& whyNot)
{
  try
  {
    return std::make_unique<MassSpringGpuSimulation>(body, scene);
  }
  catch (const GpuUnavailableError& error)
  {
    whyNot = error.what();
    return nullptr;
  }
}

} // namespace softbody::gpu
