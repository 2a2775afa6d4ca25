// Loads and boundary conditions in PBD and XPBD: prescribed points are kinematic and follow
// their keyframes exactly, a roller leaves its free components to the dynamics, and a force
// moves the centre of mass at F / M (the constraints conserve momentum), as in the mass-spring
// stepper (test_conditions.cpp).
#include "softbody/pbd/pbd_reordered.h"
#include "softbody/pbd/pbd_simulation.h"
#include "pbd_test_bodies.h"
#include "test_support.h"

#include <gtest/gtest.h>

using namespace softbody;

namespace
{

PbdSettings settingsOf(PbdFormulation formulation, const Vec3& gravity)
{
  PbdSettings settings;
  settings.formulation = formulation;
  settings.gravity = gravity;
  settings.collisions.mode = CollisionMode::Off;
  settings.timeStep = 1e-3;
  return settings;
}

constexpr PbdFormulation kBoth[] = { PbdFormulation::Pbd, PbdFormulation::Xpbd };

} // namespace

TEST(PbdConditions, PrescribedPointsFollowTheirKeyframesExactly)
{
  for (PbdFormulation formulation : kBoth)
  {
    Body body = test::pbdBoxBody(3, 0.1);
    Condition drive;
    drive.name = "drive";
    drive.kind = ConditionKind::Prescribed;
    drive.points = test::indicesWhere(body.mesh.points, [](const Vec3& p) { return p.z() < 1e-9; });
    drive.translation = Vec3(0.05, -0.02, 0.01);
    drive.rotationCenter = Vec3(0.15, 0.15, 0.0);
    drive.rotationAngle = 0.3;
    drive.profile.shape = TimeProfileShape::Keyframes;
    drive.profile.times = { 0.0, 0.1, 0.25 };
    drive.profile.factors = { 0.0, 1.0, 0.4 };
    body.conditions.push_back(drive);
    const std::vector<Vec3> rest = body.mesh.points;
    PbdSimulation sim(body, settingsOf(formulation, Vec3(0, 0, -9.81)));
    for (double t : { 0.05, 0.1, 0.2, 0.3 })
    {
      sim.advance(t);
      const double s = drive.profile.at(t);
      const Eigen::AngleAxisd turn(s * drive.rotationAngle, Vec3::UnitZ());
      double worst = 0.0;
      for (std::int32_t p : drive.points)
      {
        const Vec3& x0 = rest[static_cast<std::size_t>(p)];
        const Vec3 want = drive.rotationCenter + turn * (x0 - drive.rotationCenter) + s * drive.translation;
        worst = std::max(worst, (sim.positions()[static_cast<std::size_t>(p)] - want).norm());
      }
      EXPECT_LT(worst, 1e-15) << "t = " << t;
    }
  }
}

TEST(PbdConditions, RollerHoldsOnlyItsComponent)
{
  for (PbdFormulation formulation : kBoth)
  {
    Body body = test::pbdBoxBody(2, 0.1);
    Condition roller;
    roller.name = "roller";
    roller.points = test::indicesWhere(body.mesh.points, [](const Vec3&) { return true; });
    roller.heldAxes = { false, false, true };
    body.conditions.push_back(roller);
    const std::vector<Vec3> rest = body.mesh.points;
    PbdSimulation sim(body, settingsOf(formulation, Vec3(-2.0, 0.0, -9.81)));
    sim.advance(0.5);
    double zMoved = 0.0, xDrop = 0.0;
    for (std::size_t i = 0; i < rest.size(); ++i)
    {
      zMoved = std::max(zMoved, std::abs(sim.positions()[i].z() - rest[i].z()));
      xDrop += (rest[i].x() - sim.positions()[i].x()) / static_cast<double>(rest.size());
    }
    EXPECT_EQ(zMoved, 0.0);
    EXPECT_NEAR(xDrop, 0.25, 0.01 * 0.25);
  }
}

TEST(PbdConditions, ForceMovesTheCentreOfMassAtFOverM)
{
  for (PbdFormulation formulation : kBoth)
  {
    Body body = test::pbdBoxBody(2, 0.1);
    Condition push;
    push.name = "push";
    push.kind = ConditionKind::Force;
    push.spread = ForceSpread::PerPoint;
    push.points = test::indicesWhere(body.mesh.points, [](const Vec3& p) { return p.x() < 1e-9; });
    const Vec3 total(3.0, 0.0, 1.0);
    push.force = total / static_cast<double>(push.points.size());
    body.conditions.push_back(push);
    PbdSimulation sim(body, settingsOf(formulation, Vec3::Zero()));
    sim.advance(0.2);
    Vec3 momentum = Vec3::Zero();
    for (std::size_t i = 0; i < sim.velocities().size(); ++i)
    {
      momentum += sim.velocities()[i] / sim.inverseMasses()[i];
    }
    EXPECT_LT((momentum - 0.2 * total).norm(), 1e-9 * 0.2 * total.norm());
  }
}

TEST(PbdConditions, XpbdSupportsCarryTheWeightOfABodyAtRest)
{
  // A bar hanging from a Fixed top face, XPBD damped to rest: the support's reaction is the
  // constraints' elastic force C / alpha at the held points, and at rest it carries the body's
  // weight, M g, for the spring network from Young's modulus and both continuum models, up to
  // XPBD's own error: its rest state is the energy's equilibrium only as the substep shrinks
  // (test_xpbd_continuum.cpp), which leaves the forces out of balance sideways by about 0.1 % of
  // the weight here, and velocity damping scales gravity's increment too, by 1 - damping h per
  // substep (0.2 %).
  for (MaterialModel model : { MaterialModel::SpringNetwork, MaterialModel::Corotated, MaterialModel::StableNeoHookean })
  {
    Body body = test::pbdBoxBody(2, 0.05);
    for (Vec3& p : body.mesh.points)
    {
      p.z() *= 4.0; // 2 x 2 x 2 cells stretched to a 0.1 x 0.1 x 0.4 m bar
    }
    body.material.massDistribution = MassDistribution::LumpedVolume;
    body.material.model = model;
    Condition top;
    top.name = "top";
    top.points = test::indicesWhere(body.mesh.points, [](const Vec3& p) { return p.z() > 0.4 - 1e-9; });
    body.conditions.push_back(top);
    PbdSettings settings = settingsOf(PbdFormulation::Xpbd, Vec3(0, 0, -9.81));
    settings.timeStep = 0.0;
    settings.elasticFromMaterial = true; // E = 100 kPa, nu = 0.3: the material's defaults
    settings.substeps = 8;
    settings.damping = 2.0;
    PbdSimulation sim(body, settings);
    sim.advance(3.0);
    const ConditionReadout readout = sim.conditionReadout();
    ASSERT_EQ(readout.totals.size(), 1u) << materialModelName(model);
    const Vec3 weight = sim.totalMass() * Vec3(0, 0, 9.81);
    Vec3 sum = Vec3::Zero();
    for (std::size_t i = 0; i < readout.reactions.size(); ++i)
    {
      sum += readout.reactions[i];
      if (sim.inverseMasses()[i] > 0.0)
      {
        EXPECT_EQ(readout.reactions[i], Vec3::Zero()) << "a free point has no reaction";
      }
    }
    std::printf("%s: reaction %.5f N against the weight %.5f N (total of the condition %.5f N)\n",
      materialModelName(model), sum.z(), weight.z(), readout.totals[0].force.z());
    EXPECT_NEAR(sum.z(), weight.z(), 5e-3 * weight.z()) << materialModelName(model);
    EXPECT_LT(std::hypot(sum.x(), sum.y()), 5e-3 * weight.z()) << materialModelName(model);
    EXPECT_NEAR(readout.totals[0].force.z(), sum.z(), 1e-9 * weight.z()) << materialModelName(model);
  }
}

TEST(PbdConditions, SupportsWithoutForcesOfTheStateReactFromTheMultipliers)
{
  // PBD's stiffnesses, and XPBD's rigid constraints, are no forces of the state: the reactions
  // come from the momentum the last substep's projections gave the held points, lambda dC/dx /
  // h^2. A bar hanging from a Fixed top face and pulled down by 2 N on its bottom face, damped
  // to rest: the support carries the weight and the pull, M g + F, to the accuracy of the
  // gradient taken at the substep's end (and damping's share of gravity's increment, as above).
  // A restored frame reads the same reactions; averaged Jacobi has none and says so.
  struct Case
  {
    const char* name;
    PbdFormulation formulation;
    PbdSolver solver;
  };
  for (const Case& c : { Case{ "PBD, Gauss-Seidel", PbdFormulation::Pbd, PbdSolver::GaussSeidel },
         Case{ "PBD, Parallel Gauss-Seidel", PbdFormulation::Pbd, PbdSolver::ParallelGaussSeidel },
         Case{ "rigid XPBD, Gauss-Seidel", PbdFormulation::Xpbd, PbdSolver::GaussSeidel } })
  {
    Body body = test::pbdBoxBody(2, 0.05);
    for (Vec3& p : body.mesh.points)
    {
      p.z() *= 4.0; // a 0.1 x 0.1 x 0.4 m bar
    }
    body.material.massDistribution = MassDistribution::LumpedVolume;
    Condition top;
    top.name = "top";
    top.points = test::indicesWhere(body.mesh.points, [](const Vec3& p) { return p.z() > 0.4 - 1e-9; });
    body.conditions.push_back(top);
    Condition pull;
    pull.name = "pull";
    pull.kind = ConditionKind::Force;
    pull.spread = ForceSpread::PerPoint;
    pull.points = test::indicesWhere(body.mesh.points, [](const Vec3& p) { return p.z() < 1e-9; });
    const Vec3 load(0.0, 0.0, -2.0);
    pull.force = load / static_cast<double>(pull.points.size());
    body.conditions.push_back(pull);
    PbdSettings settings = settingsOf(c.formulation, Vec3(0, 0, -9.81));
    settings.solver = c.solver;
    settings.timeStep = 0.0;
    settings.substeps = 8;
    settings.damping = 2.0;
    PbdSimulation sim(body, settings);
    for (const std::string& w : sim.warnings())
    {
      EXPECT_EQ(w.find("reactions are not reported"), std::string::npos) << c.name << ": " << w;
    }
    sim.advance(3.0);
    const ConditionReadout readout = sim.conditionReadout();
    ASSERT_EQ(readout.totals.size(), 2u) << c.name;
    const Vec3 carried = sim.totalMass() * Vec3(0, 0, 9.81) - load;
    Vec3 sum = Vec3::Zero();
    for (std::size_t i = 0; i < readout.reactions.size(); ++i)
    {
      sum += readout.reactions[i];
      if (sim.inverseMasses()[i] > 0.0)
      {
        EXPECT_EQ(readout.reactions[i], Vec3::Zero()) << c.name << ": a free point has no reaction";
      }
    }
    std::printf("%s: reaction %.5f N against the weight and the pull %.5f N, sideways %.2e N\n", c.name,
      sum.z(), carried.z(), std::hypot(sum.x(), sum.y()));
    EXPECT_NEAR(sum.z(), carried.z(), 5e-3 * carried.z()) << c.name;
    EXPECT_LT(std::hypot(sum.x(), sum.y()), 5e-3 * carried.z()) << c.name;
    EXPECT_NEAR(readout.totals[0].force.z(), sum.z(), 1e-9 * carried.z()) << c.name;

    const DynamicState frame = sim.state();
    sim.advance(3.2);
    sim.restoreState(frame);
    const ConditionReadout restored = sim.conditionReadout();
    EXPECT_EQ(restored.totals[0].force, readout.totals[0].force) << c.name << ": a restored frame's reactions";

    // The same through the Morton-reordered simulation the filter runs: its snapshots hold the
    // support forces in the input's order, and a restored frame reads them at the right points.
    auto reordered = makePbdSimulation(body, settings, VertexOrdering::Morton);
    reordered->advance(3.0);
    const DynamicState reorderedFrame = reordered->state();
    const ConditionReadout before = reordered->conditionReadout();
    reordered->advance(3.2);
    reordered->restoreState(reorderedFrame);
    const ConditionReadout after = reordered->conditionReadout();
    ASSERT_EQ(after.reactions.size(), before.reactions.size()) << c.name;
    for (std::size_t i = 0; i < after.reactions.size(); ++i)
    {
      EXPECT_EQ(after.reactions[i], before.reactions[i]) << c.name << ": point " << i << " after a reordered restore";
    }
  }
  Body body = test::pbdBoxBody(2, 0.05);
  Condition top;
  top.name = "top";
  top.points = test::indicesWhere(body.mesh.points, [](const Vec3& p) { return p.z() > 0.1 - 1e-9; });
  body.conditions.push_back(top);
  PbdSettings jacobi = settingsOf(PbdFormulation::Pbd, Vec3(0, 0, -9.81));
  jacobi.solver = PbdSolver::Jacobi;
  PbdSimulation pbd(body, jacobi);
  pbd.advance(0.01);
  EXPECT_TRUE(pbd.conditionReadout().reactions.empty());
  bool said = false;
  for (const std::string& w : pbd.warnings())
  {
    said = said || (w.find("reactions are not reported") != std::string::npos && w.find("Solver Jacobi") != std::string::npos);
  }
  EXPECT_TRUE(said) << "Jacobi says that it reports no reactions, naming the solver";
}
