// The planners: a stage is in the plan exactly when the scene needs it, and a stage left out
// changes nothing (the same motion as the scene that does not need it).
#include "softbody/common/step_plan.h"
#include "softbody/massspring/mass_spring_plan.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"
#include "softbody/pbd/pbd_simulation.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>

using namespace softbody;

namespace
{
Body massSpringBox()
{
  Body body;
  body.mesh = makeTetBox(2, 2, 2, 0.05, Vec3(0, 0, 0.2));
  return body;
}

Body pbdBox()
{
  const TetMesh mesh = makeTetBox(2, 2, 2, 0.05, Vec3(0, 0, 0.2));
  Body body;
  body.mesh.points = mesh.points;
  body.mesh.tets = mesh.tets;
  body.material.physical.density = 1000.0;
  return body;
}

bool planHas(const Simulation& simulation, Stage stage)
{
  const std::vector<Stage> plan = simulation.plan();
  return std::find(plan.begin(), plan.end(), stage) != plan.end();
}

} // namespace

TEST(StepPlan, KeepsOrderTimesAndRefusesAStageTwice)
{
  StepPlan plan;
  plan.add(Stage::Forces, "springs");
  plan.add(Stage::Integrate, "Verlet");
  EXPECT_TRUE(plan.runs(Stage::Forces));
  EXPECT_FALSE(plan.runs(Stage::Floor));
  EXPECT_EQ(plan.stages(), (std::vector<Stage>{ Stage::Forces, Stage::Integrate }));
  EXPECT_EQ(plan.labels(), (std::vector<std::string>{ "forces: springs", "integrate: Verlet" }));
  plan.seconds(Stage::Integrate) += 0.25;
  EXPECT_EQ(plan.timings()[1].stage, Stage::Integrate);
  EXPECT_EQ(plan.timings()[1].seconds, 0.25);
  EXPECT_THROW(plan.add(Stage::Forces), std::logic_error);
}

TEST(MassSpringPlan, StrainLimitAndFloorOnlyWhenTheSceneHasThem)
{
  SceneSettings scene;
  MassSpringSimulation plain(massSpringBox(), scene);
  EXPECT_EQ(plain.plan(), (std::vector<Stage>{ Stage::Forces, Stage::Integrate, Stage::DivergenceCheck }));

  scene.strainLimit = 1.1;
  scene.floorEnabled = true;
  MassSpringSimulation busy(massSpringBox(), scene);
  // The floor is one obstacle among others: it goes through detection and the contacts.
  EXPECT_EQ(busy.plan(), (std::vector<Stage>{ Stage::Forces, Stage::Integrate, Stage::StrainLimit,
                           Stage::CollisionDetect, Stage::Contacts, Stage::DivergenceCheck }));
  busy.advance(0.01);
  EXPECT_GT(busy.stepPlan().seconds(Stage::StrainLimit), 0.0);
  EXPECT_GT(busy.stepPlan().seconds(Stage::CollisionDetect), 0.0);
  EXPECT_GT(busy.stepPlan().seconds(Stage::Contacts), 0.0);

  // The implicit integrators keep the floor in their solve; Collisions Off drops even that.
  scene.integrator = Integrator::ImplicitEuler;
  EXPECT_TRUE(planHas(MassSpringSimulation(massSpringBox(), scene), Stage::Floor));
  EXPECT_FALSE(planHas(MassSpringSimulation(massSpringBox(), scene), Stage::CollisionDetect));
  scene.collisions.mode = CollisionMode::Off;
  EXPECT_FALSE(planHas(MassSpringSimulation(massSpringBox(), scene), Stage::Floor));
  scene.integrator = Integrator::EulerCromer;
  EXPECT_FALSE(planHas(MassSpringSimulation(massSpringBox(), scene), Stage::CollisionDetect));
}

TEST(MassSpringPlan, CollisionStagesAppearWithObstaclesOrBodyCollisions)
{
  SceneSettings scene; // no floor
  MassSpringSimulation air(massSpringBox(), scene);
  EXPECT_FALSE(planHas(air, Stage::CollisionDetect));
  ObstacleSurface triangle;
  triangle.vertices = { Vec3(0, 0, -1), Vec3(1, 0, -1), Vec3(0, 1, -1) };
  triangle.triangles = { { 0, 1, 2 } };
  air.setObstacles({ triangle }, 0.0);
  EXPECT_TRUE(planHas(air, Stage::CollisionDetect));
  EXPECT_TRUE(planHas(air, Stage::Contacts));
  air.setObstacles({}, 0.0);
  EXPECT_FALSE(planHas(air, Stage::CollisionDetect));

  scene.collisions.mode = CollisionMode::ObstaclesAndBodies;
  EXPECT_TRUE(planHas(MassSpringSimulation(massSpringBox(), scene), Stage::Contacts));
}

TEST(MassSpringPlan, ForcesSayWhetherTheyIncludeVolumes)
{
  Body body = massSpringBox();
  body.material.mode = MaterialMode::Raw;
  body.material.raw.volumeStiffness = 0.0;
  body.material.raw.volumeDamping = 0.0;
  MassSpringSimulation springsOnly(body, SceneSettings{});
  EXPECT_EQ(springsOnly.stepPlan().label(Stage::Forces), "forces: springs");
  body.material.raw.volumeStiffness = 10.0;
  MassSpringSimulation withVolumes(body, SceneSettings{});
  EXPECT_EQ(withVolumes.stepPlan().label(Stage::Forces), "forces: springs + volumes");
}

TEST(PbdPlan, ZeroStiffnessVolumesAreNotSwept)
{
  PbdSettings settings;
  settings.formulation = PbdFormulation::Pbd;
  settings.volumes.stiffness = 0.0;
  PbdSimulation withoutVolumes(pbdBox(), settings);
  EXPECT_FALSE(planHas(withoutVolumes, Stage::SolveVolumes));
  EXPECT_TRUE(planHas(withoutVolumes, Stage::SolveLinks));

  // The same body with stiff volumes does sweep them.
  settings.volumes.stiffness = 1.0;
  PbdSimulation withVolumes(pbdBox(), settings);
  EXPECT_TRUE(planHas(withVolumes, Stage::SolveVolumes));

  // XPBD from Young's modulus: below Poisson's ratio 1/4 the volume term of the network
  // (lambda - mu) is not positive, so every tet compliance is infinite and nothing is swept.
  PbdSettings xpbd;
  xpbd.elasticFromMaterial = true;
  Body body = pbdBox();
  body.material.physical.poissonRatio = 0.2;
  PbdSimulation soft(body, xpbd);
  EXPECT_FALSE(planHas(soft, Stage::SolveVolumes));
  body.material.physical.poissonRatio = 0.4;
  PbdSimulation stiff(body, xpbd);
  EXPECT_TRUE(planHas(stiff, Stage::SolveVolumes));
}

TEST(PbdPlan, ZeroStiffnessLinksAreNotSweptAndTheBodyFallsFreely)
{
  // Links and volumes of PBD stiffness 0 are not swept, and nothing else acts on the body:
  // every particle falls exactly as symplectic Euler predicts (a skipped stage that still
  // moved something, or a broken prediction, would show).
  PbdSettings settings;
  settings.formulation = PbdFormulation::Pbd;
  settings.links.stiffness = 0.0;
  settings.volumes.stiffness = 0.0;
  settings.floorEnabled = false;
  PbdSimulation unconstrained(pbdBox(), settings);
  EXPECT_FALSE(planHas(unconstrained, Stage::SolveLinks));
  EXPECT_FALSE(planHas(unconstrained, Stage::SolveVolumes));
  unconstrained.advance(0.1);
  // Every particle falls as a free particle: x = x0 + g t^2 / 2 up to symplectic Euler's O(h).
  Body rest = pbdBox();
  const double t = 0.1;
  const double h = unconstrained.stepSize();
  const double steps = std::round(t / h);
  const double fall = 9.81 * h * h * steps * (steps + 1) / 2.0; // symplectic Euler, exactly
  for (std::size_t i = 0; i < rest.mesh.points.size(); ++i)
  {
    EXPECT_NEAR(unconstrained.positions()[i].z(), rest.mesh.points[i].z() - fall, 1e-12);
  }
}

TEST(PbdPlan, FloorContactsAndLinkUpdatesOnlyWhenNeeded)
{
  PbdSettings settings;
  settings.floorEnabled = false;
  PbdSimulation air(pbdBox(), settings); // one body, nothing to collide with
  EXPECT_FALSE(planHas(air, Stage::CollisionDetect));
  EXPECT_FALSE(planHas(air, Stage::SolveContacts));
  EXPECT_FALSE(planHas(air, Stage::ContactResponse));
  EXPECT_FALSE(planHas(air, Stage::UpdateLinks));
  // An obstacle arriving later puts the collision stages in; removing it takes them out.
  air.setObstacles({ ObstacleSurface{ { Vec3(-1, -1, -1), Vec3(1, -1, -1), Vec3(0, 1, -1) }, {}, { { 0, 1, 2 } } } }, 0.0);
  EXPECT_TRUE(planHas(air, Stage::CollisionDetect));
  EXPECT_TRUE(planHas(air, Stage::SolveContacts));
  air.setObstacles({}, 0.0);
  EXPECT_FALSE(planHas(air, Stage::CollisionDetect));

  settings.floorEnabled = true;
  settings.collisions.staticFriction = settings.collisions.dynamicFriction = 0.5;
  settings.collisions.restitution = 0.0;
  PbdSimulation rough(pbdBox(), settings);
  EXPECT_TRUE(planHas(rough, Stage::CollisionDetect));
  EXPECT_TRUE(planHas(rough, Stage::SolveContacts));
  EXPECT_FALSE(planHas(rough, Stage::ContactResponse)); // friction acts in the solve
  settings.collisions.restitution = 0.5;
  PbdSimulation bouncy(pbdBox(), settings);
  EXPECT_TRUE(planHas(bouncy, Stage::ContactResponse));
  settings.collisions.mode = CollisionMode::Off; // not even the floor
  PbdSimulation ghost(pbdBox(), settings);
  EXPECT_FALSE(planHas(ghost, Stage::CollisionDetect));
  EXPECT_FALSE(planHas(ghost, Stage::ContactResponse));
  settings.collisions.mode = CollisionMode::Obstacles;

  // A yield without creep never changes a rest length: no link pass, no link state.
  settings.plasticYield = 0.1;
  PbdSimulation yieldOnly(pbdBox(), settings);
  EXPECT_FALSE(planHas(yieldOnly, Stage::UpdateLinks));
  EXPECT_TRUE(yieldOnly.state().linkRestLengths.empty());
  settings.plasticCreep = 1.0;
  PbdSimulation flowing(pbdBox(), settings);
  EXPECT_TRUE(planHas(flowing, Stage::UpdateLinks));
  EXPECT_FALSE(flowing.state().linkRestLengths.empty());
  settings.plasticYield = 0.0;
  settings.breakingStrain = 0.5;
  PbdSimulation breakable(pbdBox(), settings);
  EXPECT_TRUE(planHas(breakable, Stage::UpdateLinks));
}

TEST(PbdPlan, ResidualOnlyForTheFrameLastStepOrATolerance)
{
  PbdSettings settings;
  settings.iterations = 5;
  settings.timeStep = 0.01;
  settings.reportConvergence = false;
  PbdSimulation silent(pbdBox(), settings);
  EXPECT_FALSE(planHas(silent, Stage::Residual));
  silent.advance(0.1);
  EXPECT_EQ(silent.residualEvaluations(), 0u);
  EXPECT_TRUE(silent.convergence().residualHistory.empty());

  // Reporting: only the last of the 10 steps of an advance() evaluates the residual, once per
  // iteration.
  settings.reportConvergence = true;
  PbdSimulation reporting(pbdBox(), settings);
  EXPECT_TRUE(planHas(reporting, Stage::Residual));
  reporting.advance(0.1);
  EXPECT_EQ(reporting.residualEvaluations(), 5u);
  EXPECT_EQ(reporting.convergence().residualHistory.size(), 5u);
  reporting.advance(0.2);
  EXPECT_EQ(reporting.residualEvaluations(), 10u);

  // The skipped evaluations change nothing: both runs end in the same state, bit for bit.
  silent.advance(0.2);
  EXPECT_EQ(test::maxDistance(silent.positions(), reporting.positions()), 0.0);

  // A tolerance needs the residual after every iteration of every step.
  settings.reportConvergence = false;
  settings.residualTolerance = 1e-30; // never reached: every iteration runs
  PbdSimulation tolerant(pbdBox(), settings);
  EXPECT_TRUE(planHas(tolerant, Stage::Residual));
  DynamicState stretched = tolerant.state(); // far from rest, so no step converges early
  for (Vec3& p : stretched.positions)
  {
    p *= 1.5;
  }
  tolerant.restoreState(stretched);
  tolerant.advance(0.1);
  EXPECT_EQ(tolerant.residualEvaluations(), 50u);
}

TEST(GpuAndCpuPlans, MassSpringPlannerIsTheOneSource)
{
  // The mass-spring planner is a function of the prepared body: same settings, same plan.
  SceneSettings scene;
  scene.strainLimit = 1.05;
  const MassSpringSetup setup = prepareMassSpring(massSpringBox(), scene);
  MassSpringSimulation simulation(massSpringBox(), scene);
  EXPECT_EQ(planMassSpring(setup).stages(), simulation.plan());
}
