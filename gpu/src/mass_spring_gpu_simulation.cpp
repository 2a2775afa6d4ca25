#include "softbody/gpu/mass_spring_gpu_simulation.h"
#include "softbody/mesh/volume_ratios.h"

#include "mass_spring_device.h"
#include "shared_gl_context.h"

#include "softbody/common/errors.h"
#include "softbody/gpu/gpu_errors.h"
#include "softbody/common/stepping.h"
#include "softbody/massspring/mass_spring_forces.h"
#include "softbody/massspring/mass_spring_plan.h"
#include "softbody/massspring/mass_spring_setup.h"
#include "softbody/massspring/tet_body_contacts.h"
#include "softbody/material/tet_elastic_forces.h"

#include <chrono>

namespace softbody::gpu
{

struct MassSpringGpuSimulation::Prepared
{
  MassSpringSetup setup;
  StepPlan plan; ///< core's mass-spring plan plus the transfers; timings refreshed on demand
  FloorContact floor; ///< as the CPU stepper's detector meets it
};

namespace
{

double secondsSince(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

} // namespace

MassSpringGpuSimulation::MassSpringGpuSimulation(const Body& body, const SceneSettings& scene)
  : Host(std::make_unique<Prepared>(Prepared{ prepareMassSpring(body, scene), {}, {} }))
  , State(restState(Host->setup))
{
  Host->plan = planMassSpring(Host->setup);
  Host->plan.add(Stage::Transfers);
  Host->setup.conditions.holdPoints(State.time, State.positions, State.velocities); // as the CPU starts
  const SceneSettings& prepared = Host->setup.scene;
  if (prepared.floorActive())
  {
    // Start where the CPU stepper starts the body: lifted onto the plane its contacts hold
    // points on, the floor raised by the contact thickness (the margin).
    Host->floor = floorContactOf(Host->setup.mesh, prepared);
    FloorPlane holding = prepared.floor;
    holding.origin += Host->floor.thickness * prepared.floor.normal;
    liftBodiesOntoPlane(Host->setup.mesh, Host->setup.masses.inverseMass, holding, State.positions);
  }
  Gl = SharedGlContext::acquire(); // throws GpuUnavailableError where no context can be made
  try
  {
    Gl->run([this] {
      Device = std::make_unique<MassSpringDevice>(Host->setup, Host->plan, Host->floor);
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
  if (hasDiverged(Host->setup.scene, maxStretch, finiteVelocities))
  {
    const DynamicState& current = state(); // the message names the time; the state is kept
    throw SimulationDivergedError(divergenceMessage(current, maxStretch, finiteVelocities,
                                    Host->setup.step, Host->setup.stableStep, Host->setup.selfWeight),
      current.time);
  }
}

AdvanceStatus MassSpringGpuSimulation::advance(double endTime, const ProgressCallback& progress)
{
  // Core's advance loop; each batch of steps between two divergence checks is one job on the
  // GL thread with one small read-back, instead of a round trip per step.
  const auto runSteps = [&](double h, unsigned long long count, bool) {
    // Verlet kicks by the mean of the previous and current step (core: integrateStep).
    const double firstKick = 0.5 * (State.previousStep + h);
    const double laterKick = 0.5 * (h + h);
    LastProbe = Gl->run([&] {
      double t = State.time; // core sums h within a batch, and advanceInEqualSteps sets it after
      for (unsigned long long s = 0; s < count; ++s)
      {
        Device->step(h, s == 0 ? firstKick : laterKick, t);
        t += h;
      }
      return Device->probeDivergence();
    });
    HostStale = true;
    State.stepCount += count;
  };
  return advanceInEqualSteps(State, Host->setup.step, endTime, progress, runSteps,
    [&] { checkDivergence(LastProbe.maxStretch, LastProbe.finiteVelocities); });
}

const std::vector<Vec3>& MassSpringGpuSimulation::restPositions() const
{
  return Host->setup.mesh.points;
}

const std::vector<double>& MassSpringGpuSimulation::inverseMasses() const
{
  return Host->setup.masses.inverseMass;
}

double MassSpringGpuSimulation::totalMass() const
{
  return Host->setup.masses.totalMass;
}

std::vector<double> MassSpringGpuSimulation::tetVolumeRatios() const
{
  // Only for output frames: computed on the host from the downloaded positions.
  const MassSpringSetup& s = Host->setup;
  return softbody::tetVolumeRatios(s.topology.tets, s.constants.restVolume, state().positions);
}

double MassSpringGpuSimulation::elasticEnergy() const
{
  const MassSpringSetup& s = Host->setup;
  return isContinuum(s.model) ? tetElasticEnergy(s.topology, s.tetConstants, state().positions)
                              : softbody::elasticEnergy(s.topology, s.constants, state().positions);
}

TetStressField MassSpringGpuSimulation::stressField() const
{
  // Only for output frames: computed on the host from the downloaded positions.
  const MassSpringSetup& s = Host->setup;
  return isContinuum(s.model) ? tetStressField(s.topology, s.tetConstants, state().positions) : TetStressField{};
}

ConditionReadout MassSpringGpuSimulation::conditionReadout() const
{
  const MassSpringSetup& s = Host->setup;
  if (s.conditions.empty())
  {
    return {};
  }
  const DynamicState& current = state();
  std::vector<Vec3> internal;
  if (isContinuum(s.model))
  {
    TetElasticScratch scratch;
    computeTetElasticForces(s.topology, s.tetConstants, current.positions, current.velocities, scratch, internal);
  }
  else
  {
    ForceScratch scratch;
    computeInternalForces(s.topology, s.constants, current.positions, current.velocities, scratch, internal);
  }
  return s.conditions.readout(current.time, current.positions, internal, s.masses.mass, s.scene.gravity);
}

bool MassSpringGpuSimulation::setConditionValues(const std::vector<Condition>& conditions)
{
  BoundaryConditions& held = Host->setup.conditions;
  if (!held.sameStructure(conditions))
  {
    return false;
  }
  held.replaceValues(conditions);
  Gl->run([this] { Device->conditionValuesChanged(); });
  return true;
}

double MassSpringGpuSimulation::stepSize() const
{
  return Host->setup.step;
}

double MassSpringGpuSimulation::estimatedStableStep() const
{
  return Host->setup.stableStep;
}

const std::vector<std::string>& MassSpringGpuSimulation::warnings() const
{
  return Host->setup.warnings;
}

std::string MassSpringGpuSimulation::longRunWarning(double duration) const
{
  // The CPU's throughput: llvmpipe is slower, a real GPU faster; the order of magnitude holds.
  return softbody::longRunWarning(stepCostOf(Host->setup), duration);
}

const StepPlan& MassSpringGpuSimulation::stepPlan() const
{
  // GPU times arrive through GL queries: read them when asked for, not every step.
  const std::vector<double> seconds = Gl->run([this] { return Device->stageSeconds(); });
  for (Stage stage : Host->plan.stages())
  {
    Host->plan.seconds(stage) =
      stage == Stage::Transfers ? TransferSeconds : seconds[static_cast<std::size_t>(stage)];
  }
  return Host->plan;
}

std::unique_ptr<MassSpringGpuSimulation> tryCreateGpuMassSpring(
  const Body& body, const SceneSettings& scene, std::string& whyNot)
{
  if (!factsOf(scene.integrator).runsOnGpu)
  {
    // Implicit steps need a sparse linear solve per iteration; the GPU backend is explicit.
    whyNot = std::string("the GPU backend has only the explicit integrators, and ") +
      integratorName(scene.integrator) + " is implicit.";
    return nullptr;
  }
  if (scene.stepControl == StepControl::ErrorControlled)
  {
    whyNot = "the GPU backend runs fixed steps only, and TimeStepMode is Error-controlled.";
    return nullptr;
  }
  if (body.material.volumetric == VolumetricFormulation::NodalAverage)
  {
    whyNot = "the GPU backend has each tet's own volume term only, and VolumetricFormulation is Nodal Average.";
    return nullptr;
  }
  for (const Condition& c : body.conditions)
  {
    if (c.kind == ConditionKind::Pressure || c.kind == ConditionKind::Pull)
    {
      // Their loads follow the deformed body; the GPU's loads come from the host, once per
      // change, not from the positions every step.
      whyNot = std::string("the GPU backend has Fixed, Prescribed Motion and Force conditions, not ") +
        conditionKindName(c.kind) + " (condition \"" + c.name + "\").";
      return nullptr;
    }
  }
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
