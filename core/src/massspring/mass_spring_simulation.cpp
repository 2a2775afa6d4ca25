#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/volume_ratios.h"

#include "softbody/collision/start_overlap.h"

#include "softbody/common/error_control.h"
#include "softbody/common/errors.h"
#include "softbody/massspring/bdf2.h"
#include "softbody/massspring/mass_spring_plan.h"
#include "softbody/massspring/mass_spring_setup.h"
#include "softbody/massspring/tet_body_contacts.h"

#include "softbody/common/parallel.h"
#include "softbody/common/stepping.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>


namespace softbody
{
namespace
{

/// A step split for a contact is split into at most this many pieces at once, and its pieces at
/// most this many times again (contactPieces): 64^3 pieces of a frame at the most.
constexpr int kMaxContactPieces = 64;
constexpr int kMaxContactSplitDepth = 3;

} // namespace

/// Accelerations a_i = g + w_i (f_i + loads_i) for free points, 0 for pinned and massless ones
/// and along the components conditions hold.
class MassSpringSimulation::Forces final : public AccelerationEvaluator
{
public:
  explicit Forces(const MassSpringSimulation& owner)
    : Owner(owner)
  {
  }
  void evaluate(double time, const std::vector<Vec3>& positions,
    const std::vector<Vec3>& velocities, std::vector<Vec3>& accelerations) const override
  {
    ScopedStageTimer timer(Owner.Plan, Stage::Forces);
    Owner.internalForces(positions, velocities, accelerations);
    if (Owner.Conditions.hasLoads())
    {
      Owner.Conditions.addLoads(time, positions, accelerations);
    }
    const std::vector<double>& w = Owner.Masses.inverseMass;
    const Vec3 gravity = Owner.Scene.gravity;
    parallelFor(accelerations.size(), 4096, [&](std::size_t i) {
      accelerations[i] = w[i] == 0.0 ? Vec3::Zero() : Vec3(gravity + w[i] * accelerations[i]);
    });
    Owner.Conditions.filterHeld(accelerations);
  }

private:
  const MassSpringSimulation& Owner;
};

MassSpringSimulation::MassSpringSimulation(Body body, const SceneSettings& scene)
{
  // Set-up shared with the GPU stepper (mass_spring_setup.h).
  MassSpringSetup setup = prepareMassSpring(std::move(body), scene);
  Plan = planMassSpring(
    setup.scene, elementPassLabel(setup.model, setup.constants.hasVolumeTerm), false);
  Cost = stepCostOf(setup); // before the set-up's parts move into this stepper
  Scene = setup.scene;
  State = restState(setup);
  Mesh = std::move(setup.mesh);
  Topo = std::move(setup.topology);
  Model = setup.model;
  Constants = std::move(setup.constants);
  TetConstants = std::move(setup.tetConstants);
  Masses = std::move(setup.masses);
  Conditions = std::move(setup.conditions);
  Conditions.holdPoints(State.time, State.positions, State.velocities);
  Step = setup.step;
  StableStep = setup.stableStep;
  WeightStrain = setup.selfWeight;
  OmegaMax = setup.omegaMax;
  Warnings = std::move(setup.warnings);
  if (Scene.collisions.on())
  {
    // The implicit integrators hold the floor inside their solve; the detector gets it only
    // for the explicit ones. Throws InvalidInputError for a bad margin, friction, restitution.
    Detector = std::make_unique<CollisionDetector>(tetBodyGeometry(Mesh, Scene.collisions), Scene.collisions,
      Scene.floorActive() && !isImplicit(Scene.integrator), Scene.floor);
  }
  // A contact keeps the collision margin, the floor's too: the implicit solve holds points on
  // the plane lifted by it, so every integrator rests at the same height.
  SceneSettings solveScene = Scene;
  if (Detector && solveScene.floorActive())
  {
    solveScene.floor.origin += Detector->margin() * solveScene.floor.normal;
  }
  if (solveScene.floorActive())
  {
    liftBodiesOntoPlane(Mesh, Masses.inverseMass, solveScene.floor, State.positions);
  }
  if (isImplicit(Scene.integrator))
  {
    Implicit = makeImplicitIntegrator(solveScene, Topo,
      BodyElements{ Model, &Constants, isContinuum(Model) ? &TetConstants : nullptr }, Masses,
      Mesh.points, State.positions, &Conditions);
    Implicit->contactPlanes().setElementSizes(pointElementSizes(Topo, Mesh.points));
    // The automatic step (one per advance() call: a frame) is the project's to choose, so it is
    // split where a contact needs it; a TimeStep the user set is kept and the run says what it
    // costs (landingStepWarning, fastContactSteps).
    SplitsContactSteps = !(Scene.timeStep > 0.0) && Scene.stepControl == StepControl::Fixed &&
      Scene.integrator != Integrator::Bdf2 && Scene.integrator != Integrator::Static;
  }
}

void MassSpringSimulation::internalForces(const std::vector<Vec3>& positions,
  const std::vector<Vec3>& velocities, std::vector<Vec3>& forces) const
{
  if (isContinuum(Model))
  {
    computeTetElasticForces(Topo, TetConstants, positions, velocities, TetForceWork, forces);
  }
  else
  {
    computeInternalForces(Topo, Constants, positions, velocities, ForceWork, forces);
  }
}

bool MassSpringSimulation::setConditionValues(const std::vector<Condition>& conditions)
{
  if (!Conditions.sameStructure(conditions))
  {
    return false;
  }
  Conditions.replaceValues(conditions); // the implicit potential reads the same object
  return true;
}

ConditionReadout MassSpringSimulation::conditionReadout() const
{
  if (Conditions.empty())
  {
    return {};
  }
  std::vector<Vec3> internal;
  internalForces(State.positions, State.velocities, internal);
  return Conditions.readout(State.time, State.positions, internal, Masses.mass, Scene.gravity);
}

const ImplicitConvergence* MassSpringSimulation::implicitConvergence() const
{
  return Implicit ? &Implicit->convergence() : nullptr;
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

double MassSpringSimulation::elasticEnergy() const
{
  return isContinuum(Model) ? tetElasticEnergy(Topo, TetConstants, State.positions)
                            : softbody::elasticEnergy(Topo, Constants, State.positions);
}

double MassSpringSimulation::mechanicalEnergy() const
{
  // The elastic energy first, then each point's kinetic energy: the order the sum always had.
  double energy = elasticEnergy();
  for (std::size_t i = 0; i < State.velocities.size(); ++i)
  {
    energy += 0.5 * Masses.mass[i] * State.velocities[i].squaredNorm();
  }
  return energy;
}

TetStressField MassSpringSimulation::stressField() const
{
  return isContinuum(Model) ? tetStressField(Topo, TetConstants, State.positions) : TetStressField{};
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
  // The stepper times its element passes (Forces), solves (LinearSolve) and floor active set
  // (Floor); the rest of its time (vector updates, line-search bookkeeping) is Integrate.
  const auto timedInside = [this] {
    return Plan.seconds(Stage::Forces) + Plan.seconds(Stage::LinearSolve) + Plan.seconds(Stage::Floor);
  };
  const double before = timedInside();
  double total = 0.0;
  {
    ScopedStageTimer timer(total);
    Implicit->step(h, State, Plan);
  }
  if (std::string warning = Implicit->solverWarning();
      !warning.empty() && std::find(Warnings.begin(), Warnings.end(), warning) == Warnings.end())
  {
    Warnings.push_back(std::move(warning));
  }
  Plan.seconds(Stage::Integrate) += total - (timedInside() - before);
  State.time += h;
  State.previousStep = h;
  ++State.stepCount;
}

void MassSpringSimulation::stepOnce(double h)
{
  stepSplittingContacts(h, 0);
}

void MassSpringSimulation::stepSplittingContacts(double h, int depth)
{
  if (Implicit && Detector && (HasObstacles || Scene.collisions.bodiesCollide()))
  {
    findObstaclePlanes(h);
  }
  if (Implicit && !Implicit->contactPlanes().empty())
  {
    // Each piece finds its planes again over its own, shorter sweep, and is split again if a
    // point still comes too fast (it accelerated); kMaxContactSplitDepth bounds that.
    if (const int pieces = depth < kMaxContactSplitDepth ? contactPieces(h) : 1; pieces > 1)
    {
      ImplicitConvergence& report = Implicit->convergence();
      ++report.contactSplitSteps;
      report.contactSplitPieces += static_cast<unsigned long long>(pieces);
      for (int piece = 0; piece < pieces; ++piece)
      {
        stepSplittingContacts(h / pieces, depth + 1);
      }
      return;
    }
    noteFastApproach(h);
  }
  takeStep(h);
}

int MassSpringSimulation::contactPieces(double h) const
{
  if (!SplitsContactSteps)
  {
    return 1;
  }
  const double ratio = fastestApproach(
    Implicit->contactPlanes(), State.positions, State.velocities, Masses.inverseMass, h).ratio();
  return ratio > kContactApproachFraction
    ? static_cast<int>(std::min(std::ceil(ratio / kContactApproachFraction), double(kMaxContactPieces)))
    : 1;
}

std::string MassSpringSimulation::landingStepWarning(double step) const
{
  // Error-controlled steps shorten themselves where the landing needs it, and so does the
  // automatic step (contactPieces).
  if (!Implicit || !Scene.floorActive() || !(step > 0.0) || !std::isfinite(step) ||
    Scene.stepControl == StepControl::ErrorControlled || SplitsContactSteps)
  {
    return "";
  }
  const ContactPlanes& planes = Implicit->contactPlanes();
  std::int32_t bodies = 0;
  const std::vector<std::int32_t> bodyOf = bodyOfPoints(Mesh, bodies);
  const LandingApproach landing = floorLandingApproach(planes, Scene.floor, Scene.gravity, State.positions,
    State.velocities, Masses.inverseMass, bodyOf, bodies, step);
  if (!landing.approach.tooFast())
  {
    return "";
  }
  std::ostringstream message;
  message.precision(3);
  message << integratorName(Scene.integrator) << " at a step of " << step << " s: the body will reach the floor at about "
          << landing.speed << " m/s (falling " << landing.height << " m) and move " << landing.approach.approach
          << " m in its landing step, against elements of " << landing.approach.size
          << " m: that step crushes the elements where it lands (inverted tets). Take a TimeStep of at most "
          << step * kContactApproachFraction / landing.approach.ratio()
          << " s (TimeStep 0, automatic, splits the landing steps so), or an explicit integrator.";
  return message.str();
}

void MassSpringSimulation::noteFastApproach(double h)
{
  // A point that moves into its plane by more than its elements in one step stops there while
  // the points above it do not: the step crushes the elements between (a torus landing at
  // 1/20 s, 1.8 m/s, on 3 cm elements). Counted for the report, which gives the TimeStep that
  // avoids it.
  const ContactApproach fastest = fastestApproach(
    Implicit->contactPlanes(), State.positions, State.velocities, Masses.inverseMass, h);
  if (!fastest.tooFast())
  {
    return;
  }
  ImplicitConvergence& report = Implicit->convergence();
  ++report.fastContactSteps;
  if (report.fastestApproachSize > 0.0 &&
    fastest.ratio() <= report.fastestApproach / report.fastestApproachSize)
  {
    return; // not the worst so far
  }
  report.fastestApproach = fastest.approach;
  report.fastestApproachStep = h;
  report.fastestApproachSize = fastest.size;
}

void MassSpringSimulation::takeStep(double h)
{
  if (Plan.runs(Stage::CollisionDetect))
  {
    StepStart = State.positions;
  }
  if (Implicit)
  {
    integrateImplicit(h);
  }
  else
  {
    integrateExplicit(h);
  }
  if (Scene.integrator == Integrator::Bdf2)
  {
    SolvedVelocities = State.velocities;
  }
  // The held components where their conditions put them at the step's end (the integrators
  // moved them by their velocity; the implicit solve left fully held points where they were).
  Conditions.holdPoints(State.time, State.positions, State.velocities);
  if (Plan.runs(Stage::StrainLimit))
  {
    ScopedStageTimer timer(Plan, Stage::StrainLimit);
    // Verlet's velocity is the position difference of the last step: a moved point moves it.
    limitStrain(Topo, Constants, Masses.inverseMass, Scene.strainLimit,
      Scene.strainLimitIterations, factsOf(Scene.integrator).velocityFromPositions, h, State.positions,
      State.velocities, StrainWork);
  }
  if (Plan.runs(Stage::CollisionDetect))
  {
    resolveContacts(h);
  }
  if (Scene.integrator == Integrator::Bdf2)
  {
    restartCorrectedHistories();
  }
}

void MassSpringSimulation::markPointsInContact(std::vector<char>& mask) const
{
  if (Implicit && !Implicit->contactPlanes().empty())
  {
    // On its plane, to within a small part of its elements (the solve holds it there).
    const ContactPlanes& planes = Implicit->contactPlanes();
    parallelFor(mask.size(), 4096, [&](std::size_t i) {
      if (planes.has(i) && planes.depth(i, State.positions[i]) <= kContactBand * planes.elementSize(i))
      {
        mask[i] = 1;
      }
    });
  }
  markContactPoints(Contacts, mask); // the response after the step (explicit integrators, bodies)
}

double MassSpringSimulation::largestLocalError(const EmbeddedErrorEstimate& estimate, const DynamicState& start,
  double h, const std::vector<char>& skip)
{
  LocalErrors.resize(State.positions.size());
  parallelFor(LocalErrors.size(), 4096, [&](std::size_t i) {
    // A held component moves as its condition says: it has no error to estimate.
    LocalErrors[i] = Masses.inverseMass[i] == 0.0 || skip[i] ? Vec3::Zero() : estimate.pointError(start, State, h, i);
  });
  Conditions.filterHeld(LocalErrors);
  double largest = 0.0;
  for (const Vec3& e : LocalErrors)
  {
    const double size = e.norm();
    largest = std::isnan(size) ? std::numeric_limits<double>::infinity() : std::max(largest, size);
  }
  return largest;
}

void MassSpringSimulation::restartCorrectedHistories()
{
  // The corrections after the solve (held components, strain limit, contact response) change
  // velocities the history does not know of.
  parallelFor(State.velocities.size(), 4096, [&](std::size_t i) {
    if (State.velocities[i] != SolvedVelocities[i])
    {
      restartBdf2History(i, State);
    }
  });
}

void MassSpringSimulation::findObstaclePlanes(double h)
{
  // The obstacle faces, and other bodies' faces, each point may reach in the step, from a sweep
  // to the explicit prediction x0 + h v0 + h^2 g: the implicit solve then keeps the points in
  // front of them (contact_planes.h).
  ScopedStageTimer timer(Plan, Stage::CollisionDetect);
  const std::vector<double>& w = Masses.inverseMass;
  Predicted.resize(State.positions.size());
  parallelFor(Predicted.size(), 4096, [&](std::size_t i) {
    Predicted[i] = w[i] == 0.0 ? State.positions[i]
                               : Vec3(State.positions[i] + h * State.velocities[i] + (h * h) * Scene.gravity);
  });
  Detector->detect(State.positions, Predicted, State.time, h, PlaneContacts);
  ContactPlanes& planes = Implicit->contactPlanes();
  planes.reset(State.positions.size());
  planes.addContacts(PlaneContacts, State.positions, Predicted, State.velocities);
}

void MassSpringSimulation::resolveContacts(double h)
{
  {
    ScopedStageTimer timer(Plan, Stage::CollisionDetect);
    // Swept from the step's start: a point that crossed something within the step is found.
    Detector->detect(StepStart, State.positions, State.time - h, h, Contacts);
  }
  if (Implicit && HasObstacles)
  {
    dropObstacleContactsHeldInTheSolve();
  }
  ScopedStageTimer timer(Plan, Stage::Contacts);
  ContactStats = respondToContacts(Contacts, Scene.collisions, Masses.inverseMass, StepStart, h,
    State.positions, State.velocities);
}

void MassSpringSimulation::dropObstacleContactsHeldInTheSolve()
{
  // The implicit solve held its points on the obstacles' planes and gave them the contact
  // response (inelastic, friction): responding again would apply friction twice. What is left
  // for the response is a point deeper than the solve's rounding: one whose plane did not
  // cover its obstacle (a concave face, a face it was not heading for at the step's start).
  std::erase_if(Contacts, [&](const Contact& c) {
    if (c.kind != ContactKind::Obstacle)
    {
      return false;
    }
    const Vec3& x = State.positions[static_cast<std::size_t>(c.point)];
    const double C = c.normal.dot(x - c.surfacePoint) - c.thickness;
    const double rounding = 1.0e-6 * c.thickness + 64.0 * std::numeric_limits<double>::epsilon() * x.norm();
    return C >= -rounding;
  });
}

void MassSpringSimulation::setObstacles(std::vector<ObstacleSurface> obstacles, double endTime)
{
  if (!Detector)
  {
    return; // Collisions Off: nothing is collided with
  }
  const bool hasObstacles = !obstacles.empty();
  Detector->setObstacles(std::move(obstacles), endTime);
  // Bodies placed across an obstacle are said to be, once, where the run starts.
  noteObstacleStart(*Detector, State.positions, State.time, ObstacleStartChecked, Warnings);
  if (hasObstacles != HasObstacles)
  {
    // The collision stages appear (or go) with the obstacles; set before the first advance,
    // as the filter does, no stage time is lost.
    HasObstacles = hasObstacles;
    Plan = planMassSpring(Scene, elementPassLabel(Model, Constants.hasVolumeTerm), HasObstacles);
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
      divergenceMessage(State, stretch, finiteVelocities, Step, StableStep, WeightStrain), State.time);
  }
}

AdvanceStatus MassSpringSimulation::advance(double endTime, const ProgressCallback& progress)
{
  if (Scene.stepControl == StepControl::ErrorControlled)
  {
    // An explicit integrator stays within its stable step; the user's TimeStep bounds any.
    ErrorControl control{ Scene.errorTolerance, factsOf(Scene.integrator).order, Step };
    const EmbeddedErrorEstimate* embedded = factsOf(Scene.integrator).localError;
    if (embedded && !Scene.stepDoubling)
    {
      if (embedded == &kVerletEstimate && State.previousAccelerations.size() != State.positions.size())
      {
        // The estimate's history starts here; until a step has written it, a step with a
        // history says more than it knows, so the zeros only shorten the next step.
        State.previousAccelerations.assign(State.positions.size(), Vec3::Zero());
      }
      control.localError = [this, embedded](const DynamicState& start, const DynamicState&, double h,
                             const std::vector<char>& skip) { return largestLocalError(*embedded, start, h, skip); };
      control.errorConstant = embedded->constant;
    }
    else if (Scene.integrator == Integrator::Bdf2)
    {
      control.halvesErrorFactor = bdf2HalvesErrorFactor;
    }
    if (StableStep > 0.0)
    {
      control.maxStep = std::min(control.maxStep, Scene.stabilitySafety * StableStep);
    }
    return advanceWithErrorControl(State, control, endTime, progress, [&](double h) { stepOnce(h); },
      [&] { checkDivergence(); }, [&](std::vector<char>& mask) { markPointsInContact(mask); }, StepReport);
  }
  const auto stepOnceAt = [&](double h, bool) { stepOnce(h); };
  return advanceInEqualSteps(State, Step, endTime, progress, oneStepAtATime(stepOnceAt),
    [&] { checkDivergence(); });
}

} // namespace softbody
