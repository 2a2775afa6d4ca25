#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/volume_ratios.h"

#include "softbody/common/errors.h"
#include "softbody/massspring/mass_spring_plan.h"
#include "softbody/massspring/mass_spring_setup.h"

#include "softbody/common/parallel.h"
#include "softbody/common/stepping.h"
#include "softbody/mesh/components.h"

#include <algorithm>
#include <numeric>


namespace softbody
{
namespace
{
/// What the detector collides of a tet body: its boundary triangles (outward), each point's
/// connected body; no particles (radius 0). The colliding points are all points, so that a
/// body crushed through its own bottom (a very soft one, a fast impact) still keeps every
/// point out of the floor and the obstacles, as the floor pass before did; with self
/// collisions only the surface vertices, since an interior point lies behind its own
/// surface's one-sided triangles and would be pushed out through them.
CollisionGeometry tetBodyGeometry(const TetMesh& mesh, CollisionMode mode)
{
  CollisionGeometry g;
  g.rest = mesh.points;
  g.radius.assign(mesh.points.size(), 0.0);
  std::vector<std::int64_t> offsets(mesh.tets.size() + 1);
  std::vector<std::int64_t> cellPoints;
  cellPoints.reserve(4 * mesh.tets.size());
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
  {
    offsets[t] = static_cast<std::int64_t>(4 * t);
    for (std::int32_t v : mesh.tets[t])
    {
      cellPoints.push_back(v);
    }
  }
  offsets.back() = static_cast<std::int64_t>(cellPoints.size());
  const Components components = connectedComponents(mesh.points.size(), offsets, cellPoints);
  g.bodyOf.assign(mesh.points.size(), -1);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
  {
    for (std::int32_t v : mesh.tets[t])
    {
      g.bodyOf[v] = components.ofCell[t];
    }
  }
  // Points in no tet belong to no body and collide with nothing; give each its own number.
  std::int32_t next = components.count;
  for (std::int32_t& body : g.bodyOf)
  {
    body = body < 0 ? next++ : body;
  }
  g.surfaceTriangles = boundaryTriangles(mesh.tets);
  if (mode != CollisionMode::ObstaclesBodiesAndSelf)
  {
    g.collidingPoints.resize(mesh.points.size());
    std::iota(g.collidingPoints.begin(), g.collidingPoints.end(), 0);
    return g;
  }
  for (const auto& triangle : g.surfaceTriangles)
  {
    g.collidingPoints.insert(g.collidingPoints.end(), triangle.begin(), triangle.end());
  }
  std::sort(g.collidingPoints.begin(), g.collidingPoints.end());
  g.collidingPoints.erase(
    std::unique(g.collidingPoints.begin(), g.collidingPoints.end()), g.collidingPoints.end());
  return g;
}
} // namespace

SceneSettings floorPassScene(const TetMesh& mesh, const SceneSettings& scene)
{
  SceneSettings lifted = scene;
  if (!scene.floorEnabled || scene.collisions.mode == CollisionMode::Off)
  {
    return lifted;
  }
  const CollisionDetector detector(tetBodyGeometry(mesh, scene.collisions.mode), scene.collisions,
    false, scene.floor);
  if (scene.floor.normal.norm() > 0.0)
  {
    lifted.floor.origin += detector.margin() * scene.floor.normal.normalized();
  }
  return lifted;
}

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
    ScopedStageTimer timer(Owner.Plan, Stage::Forces);
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
{
  // Set-up shared with the GPU stepper (mass_spring_setup.h).
  MassSpringSetup setup = prepareMassSpring(std::move(body), scene);
  Plan = planMassSpring(setup.scene, setup.constants.hasVolumeTerm, false);
  Cost = stepCostOf(setup); // before the set-up's parts move into this stepper
  Scene = setup.scene;
  State = restState(setup);
  Mesh = std::move(setup.mesh);
  Topo = std::move(setup.topology);
  Constants = std::move(setup.constants);
  Masses = std::move(setup.masses);
  Step = setup.step;
  StableStep = setup.stableStep;
  OmegaMax = setup.omegaMax;
  Warnings = std::move(setup.warnings);
  if (Scene.collisions.mode != CollisionMode::Off)
  {
    // The implicit integrators hold the floor inside their solve; the detector gets it only
    // for the explicit ones. Throws InvalidInputError for a bad margin, friction, restitution.
    Detector = std::make_unique<CollisionDetector>(tetBodyGeometry(Mesh, Scene.collisions.mode), Scene.collisions,
      Scene.floorEnabled && !isImplicit(Scene.integrator), Scene.floor);
  }
  // A contact keeps the collision margin, the floor's too: the implicit solve holds points on
  // the plane lifted by it, so every integrator rests at the same height.
  SceneSettings solveScene = Scene;
  if (Detector && solveScene.floorEnabled)
  {
    solveScene.floor.origin += Detector->margin() * solveScene.floor.normal;
  }
  if (Scene.integrator == Integrator::ImplicitEuler)
  {
    Newton = std::make_unique<ImplicitEulerStepper>(Topo, Constants, Masses, solveScene);
  }
  else if (Scene.integrator == Integrator::ProjectiveDynamics)
  {
    Projective =
      std::make_unique<ProjectiveDynamicsStepper>(Topo, Constants, Masses, Mesh.points, solveScene);
  }
}

const ImplicitConvergence* MassSpringSimulation::implicitConvergence() const
{
  if (Newton)
  {
    return &Newton->convergence();
  }
  return Projective ? &Projective->convergence() : nullptr;
}

std::string MassSpringSimulation::longRunWarning(double duration) const
{
  return softbody::longRunWarning(Cost, duration);
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

double MassSpringSimulation::mechanicalEnergy() const
{
  double energy = elasticEnergy(Topo, Constants, State.positions);
  for (std::size_t i = 0; i < State.velocities.size(); ++i)
  {
    energy += 0.5 * Masses.mass[i] * State.velocities[i].squaredNorm();
  }
  return energy;
}

std::vector<double> MassSpringSimulation::tetVolumeRatios() const
{
  return softbody::tetVolumeRatios(Topo.tets, Constants.restVolume, State.positions);
}

void MassSpringSimulation::integrateExplicit(double h)
{
  // The integrator evaluates the forces (timed as Stage::Forces); Integrate is its own time.
  const double forcesBefore = Plan.seconds(Stage::Forces);
  double integrateAndForces = 0.0;
  {
    ScopedStageTimer timer(integrateAndForces);
    integrateStep(Scene.integrator, h, Forces(*this), State, IntegratorWork);
  }
  Plan.seconds(Stage::Integrate) += integrateAndForces - (Plan.seconds(Stage::Forces) - forcesBefore);
}

void MassSpringSimulation::integrateImplicit(double h)
{
  // The stepper times its element passes (Forces) and solves (LinearSolve); the rest of its
  // time (vector updates, line-search bookkeeping) is Integrate.
  const double before = Plan.seconds(Stage::Forces) + Plan.seconds(Stage::LinearSolve);
  double total = 0.0;
  {
    ScopedStageTimer timer(total);
    if (Newton)
    {
      Newton->step(h, State, Plan);
    }
    else
    {
      Projective->step(h, State, Plan);
    }
  }
  Plan.seconds(Stage::Integrate) +=
    total - (Plan.seconds(Stage::Forces) + Plan.seconds(Stage::LinearSolve) - before);
  State.time += h;
  State.previousStep = h;
  ++State.stepCount;
}

void MassSpringSimulation::stepOnce(double h)
{
  if (Plan.runs(Stage::CollisionDetect))
  {
    StepStart = State.positions;
  }
  if (isImplicit(Scene.integrator))
  {
    integrateImplicit(h);
  }
  else
  {
    integrateExplicit(h);
  }
  if (Plan.runs(Stage::StrainLimit))
  {
    ScopedStageTimer timer(Plan, Stage::StrainLimit);
    // Verlet's velocity is the position difference of the last step: a moved point moves it.
    limitStrain(Topo, Constants, Masses.inverseMass, Scene.strainLimit,
      Scene.strainLimitIterations, Scene.integrator == Integrator::Verlet, h, State.positions,
      State.velocities, StrainWork);
  }
  if (Plan.runs(Stage::CollisionDetect))
  {
    resolveContacts(h);
  }
}

void MassSpringSimulation::resolveContacts(double h)
{
  {
    ScopedStageTimer timer(Plan, Stage::CollisionDetect);
    // Swept from the step's start: a point that crossed something within the step is found.
    Detector->detect(StepStart, State.positions, State.time - h, h, Contacts);
  }
  ScopedStageTimer timer(Plan, Stage::Contacts);
  ContactStats = respondToContacts(Contacts, Scene.collisions, Masses.inverseMass, StepStart, h,
    State.positions, State.velocities);
}

void MassSpringSimulation::setObstacles(std::vector<ObstacleSurface> obstacles, double endTime)
{
  if (!Detector)
  {
    return; // Collisions Off: nothing is collided with
  }
  const bool hasObstacles = !obstacles.empty();
  Detector->setObstacles(std::move(obstacles), endTime);
  if (hasObstacles != HasObstacles)
  {
    // The collision stages appear (or go) with the obstacles; set before the first advance,
    // as the filter does, no stage time is lost.
    HasObstacles = hasObstacles;
    Plan = planMassSpring(Scene, Constants.hasVolumeTerm, HasObstacles);
  }
}

void MassSpringSimulation::checkDivergence() const
{
  ScopedStageTimer timer(Plan, Stage::DivergenceCheck);
  const double stretch = maxStretchRatio(Topo, Constants, State.positions);
  bool finiteVelocities = true;
  for (const Vec3& v : State.velocities)
  {
    finiteVelocities = finiteVelocities && v.allFinite();
  }
  if (hasDiverged(Scene, stretch, finiteVelocities))
  {
    throw SimulationDivergedError(
      divergenceMessage(State, stretch, finiteVelocities, Step, StableStep), State.time);
  }
}

AdvanceStatus MassSpringSimulation::advance(double endTime, const ProgressCallback& progress)
{
  const auto stepOnceAt = [&](double h, bool) { stepOnce(h); };
  return advanceInEqualSteps(State, Step, endTime, progress, oneStepAtATime(stepOnceAt),
    [&] { checkDivergence(); });
}

} // namespace softbody
