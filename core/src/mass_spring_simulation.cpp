#include "softbody/mass_spring_simulation.h"

#include "softbody/errors.h"
#include "softbody/stability.h"

#include "softbody/parallel.h"
#include "softbody/stepping.h"

#include <cmath>
#include <sstream>

namespace softbody
{
namespace
{

// Stage indices into StageSeconds, in step order.
enum Stage
{
  kForces,
  kIntegrate,
  kStrainLimit,
  kFloor,
  kDivergenceCheck,
  kStageCount
};
constexpr const char* kStageNames[kStageCount] = { "forces", "integrate", "strain limit", "floor",
  "divergence check" };

// A divergence check costs one pass over the edges; every few steps is enough to stop within
// a small fraction of a frame.
constexpr unsigned long long kDivergenceCheckInterval = 16;

void validateScene(const SceneSettings& scene)
{
  auto fail = [](const std::string& message) { throw InvalidInputError(message); };
  if (!(scene.timeStep >= 0.0) || !std::isfinite(scene.timeStep))
  {
    fail("TimeStep must be 0 (automatic) or a positive number of seconds.");
  }
  if (!scene.gravity.allFinite())
  {
    fail("Gravity must be finite.");
  }
  if (scene.floorEnabled && (!(scene.floor.normal.norm() > 0.0) || !scene.floor.normal.allFinite() ||
                              !scene.floor.origin.allFinite()))
  {
    fail("FloorNormal must be a nonzero finite vector and FloorOrigin finite.");
  }
  if (scene.strainLimit != 0.0 && !(scene.strainLimit > 1.0))
  {
    fail("StrainLimit must be 0 (off) or a stretch factor greater than 1.");
  }
  if (scene.strainLimitIterations < 1)
  {
    fail("StrainLimitIterations must be at least 1.");
  }
  if (!(scene.stabilitySafety > 0.0 && scene.stabilitySafety <= 1.0))
  {
    fail("The stability safety factor must be in (0, 1].");
  }
}

} // namespace

/// Accelerations a_i = g + w_i f_i for free points, 0 for pinned and massless ones.
class MassSpringSimulation::Forces final : public AccelerationEvaluator
{
public:
  explicit Forces(const MassSpringSimulation& owner)
    : Owner(owner)
  {
  }
  void evaluate(const std::vector<Vec3>& positions, const std::vector<Vec3>& velocities,
    std::vector<Vec3>& accelerations) const override
  {
    ScopedStageTimer timer(Owner.StageSeconds[kForces]);
    computeInternalForces(
      Owner.Topo, Owner.Constants, positions, velocities, Owner.ForceWork, accelerations);
    const std::vector<double>& w = Owner.Masses.inverseMass;
    const Vec3 gravity = Owner.Scene.gravity;
    parallelFor(accelerations.size(), 4096, [&](std::size_t i) {
      accelerations[i] = w[i] == 0.0 ? Vec3::Zero() : Vec3(gravity + w[i] * accelerations[i]);
    });
  }

private:
  const MassSpringSimulation& Owner;
};

MassSpringSimulation::MassSpringSimulation(BodyDescription body, const SceneSettings& scene)
  : Scene(scene)
  , StageSeconds(kStageCount, 0.0)
{
  validateScene(Scene);
  if (!body.pinned.empty() && body.pinned.size() != body.mesh.points.size())
  {
    throw InvalidInputError("The pinned-point flags do not match the number of points.");
  }
  Mesh = prepareTetMesh(std::move(body.mesh), Scene.invertedTets, Warnings);
  Topo = buildTopology(Mesh.points.size(), Mesh.tets);
  Constants = computeElementConstants(Topo, Mesh.points, body.material, Warnings);

  double restVolume = 0.0;
  for (double v : Constants.restVolume)
  {
    restVolume += v;
  }
  Masses = distributeMass(Topo, Constants.restVolume, totalMassOf(body.material, restVolume),
    body.material.massDistribution, body.material.maxInverseMass, body.pinned);
  if (Masses.truncatedCount > 0)
  {
    std::ostringstream message;
    message << Masses.truncatedCount << " inverse masses were truncated to "
            << body.material.maxInverseMass << " 1/kg; the total mass grew to " << Masses.totalMass
            << " kg.";
    Warnings.push_back(message.str());
  }

  Scene.floor.normal.normalize();
  if (Scene.floorEnabled)
  {
    std::size_t below = 0;
    for (const Vec3& p : Mesh.points)
    {
      below += (p - Scene.floor.origin).dot(Scene.floor.normal) < 0.0 ? 1 : 0;
    }
    if (below > 0)
    {
      // Projecting them all at once crushes the tets they belong to: usually not intended.
      Warnings.push_back(std::to_string(below) +
        " points start below the floor and will be pushed onto it in the first step; move "
        "FloorOrigin below the body to drop it instead.");
    }
  }
  State.positions = Mesh.points;
  State.velocities.assign(Mesh.points.size(), Vec3::Zero());

  OmegaMax = highestFrequencyBound(Topo, Constants, Masses.inverseMass, Mesh.points);
  StableStep = stableTimeStep(
    Scene.integrator, OmegaMax, Constants.minDampingTime, Constants.maxDampingTime);
  const double symplecticStep =
    stableTimeStep(Integrator::EulerCromer, OmegaMax, Constants.minDampingTime, Constants.maxDampingTime);
  if (Scene.timeStep > 0.0)
  {
    Step = Scene.timeStep;
    if (StableStep > 0.0 && Step > StableStep)
    {
      std::ostringstream message;
      message << "TimeStep " << Step << " s is above the estimated stable step " << StableStep
              << " s of " << integratorName(Scene.integrator)
              << "; the simulation may blow up (set TimeStep to 0 for automatic).";
      Warnings.push_back(message.str());
    }
  }
  else if (StableStep > 0.0)
  {
    Step = Scene.stabilitySafety * StableStep;
  }
  else if (symplecticStep > 0.0)
  {
    // Explicit Euler without damping amplifies every oscillation at any step size.
    Step = 0.1 * Scene.stabilitySafety * symplecticStep;
    std::ostringstream message;
    message << integratorName(Scene.integrator)
            << " has no stable step without damping: oscillations grow at any step. Using "
            << Step << " s; add damping or choose Euler-Cromer or Verlet.";
    Warnings.push_back(message.str());
  }
  else
  {
    Step = 1e-3; // no internal stiffness at all (e.g. zero constants): any step is stable
  }
}

void MassSpringSimulation::restoreState(const DynamicState& snapshot)
{
  if (snapshot.positions.size() != State.positions.size() ||
      snapshot.velocities.size() != State.velocities.size())
  {
    throw InvalidInputError("The snapshot does not belong to this simulation.");
  }
  State = snapshot;
}

std::vector<StageTiming> MassSpringSimulation::stageTimings() const
{
  // Only the stages this scene runs, named for what they do here. "integrate" was timed around
  // the force evaluations too; it is reported net of them.
  std::vector<StageTiming> timings;
  timings.push_back({ Constants.hasVolumeTerm ? "forces: springs + volumes" : "forces: springs",
    StageSeconds[kForces] });
  timings.push_back({ std::string("integrate: ") + integratorName(Scene.integrator),
    StageSeconds[kIntegrate] - StageSeconds[kForces] });
  if (Scene.strainLimit > 0.0)
  {
    timings.push_back({ kStageNames[kStrainLimit], StageSeconds[kStrainLimit] });
  }
  if (Scene.floorEnabled)
  {
    timings.push_back({ kStageNames[kFloor], StageSeconds[kFloor] });
  }
  timings.push_back({ kStageNames[kDivergenceCheck], StageSeconds[kDivergenceCheck] });
  return timings;
}

std::vector<double> MassSpringSimulation::tetVolumeRatios() const
{
  std::vector<double> ratios(Topo.tets.size());
  const std::vector<Vec3>& x = State.positions;
  for (std::size_t t = 0; t < Topo.tets.size(); ++t)
  {
    const Tet& tet = Topo.tets[t];
    ratios[t] = signedTetVolume(x[tet[0]], x[tet[1]], x[tet[2]], x[tet[3]]) / Constants.restVolume[t];
  }
  return ratios;
}

void MassSpringSimulation::stepOnce(double h)
{
  {
    ScopedStageTimer timer(StageSeconds[kIntegrate]);
    integrateStep(Scene.integrator, h, Forces(*this), State, IntegratorWork);
  }
  if (Scene.strainLimit > 0.0)
  {
    ScopedStageTimer timer(StageSeconds[kStrainLimit]);
    // Verlet's velocity is the position difference of the last step: a moved point moves it.
    limitStrain(Topo, Constants, Masses.inverseMass, Scene.strainLimit,
      Scene.strainLimitIterations, Scene.integrator == Integrator::Verlet, h, State.positions,
      State.velocities, StrainWork);
  }
  if (Scene.floorEnabled)
  {
    ScopedStageTimer timer(StageSeconds[kFloor]);
    resolveFloorContacts(Scene.floor, Masses.inverseMass, State.positions, State.velocities);
  }
}

void MassSpringSimulation::checkDivergence() const
{
  ScopedStageTimer timer(StageSeconds[kDivergenceCheck]);
  const double stretch = maxStretchRatio(Topo, Constants, State.positions);
  bool finiteVelocities = true;
  for (const Vec3& v : State.velocities)
  {
    finiteVelocities = finiteVelocities && v.allFinite();
  }
  if (stretch <= Scene.divergenceStretch && finiteVelocities)
  {
    return;
  }
  std::ostringstream message;
  message << "The simulation blew up at t = " << State.time << " s (step " << State.stepCount
          << "): ";
  if (std::isnan(stretch) || !finiteVelocities)
  {
    message << "the state became non-finite";
  }
  else
  {
    message << "a spring stretched to " << stretch << " times its rest length";
  }
  message << ". Time step " << Step << " s, estimated stable step " << StableStep
          << " s; reduce TimeStep (0 = automatic), add damping or use a symplectic integrator.";
  throw SimulationDivergedError(message.str(), State.time);
}

AdvanceStatus MassSpringSimulation::advance(double endTime, const ProgressCallback& progress)
{
  return advanceInEqualSteps(State, Step, endTime, progress, kDivergenceCheckInterval,
    [&](double h, bool) { stepOnce(h); }, [&] { checkDivergence(); });
}

} // namespace softbody
