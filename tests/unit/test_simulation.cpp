// Whole-simulation behaviour: landing on the floor, pins, conservation, input errors.
#include "softbody/common/errors.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"
#include "test_support.h"

#include <gtest/gtest.h>

using namespace softbody;

namespace
{

Body boxBody(const Vec3& origin = Vec3(0, 0, 0.2))
{
  Body body;
  body.mesh = makeTetBox(3, 3, 3, 0.05, origin);
  return body;
}

Vec3 linearMomentum(const MassSpringSimulation& sim)
{
  Vec3 p = Vec3::Zero();
  for (std::size_t i = 0; i < sim.positions().size(); ++i)
  {
    p += sim.masses()[i] * sim.velocities()[i];
  }
  return p;
}

Vec3 angularMomentum(const MassSpringSimulation& sim)
{
  Vec3 l = Vec3::Zero();
  for (std::size_t i = 0; i < sim.positions().size(); ++i)
  {
    l += sim.masses()[i] * sim.positions()[i].cross(sim.velocities()[i]);
  }
  return l;
}

/// The GPU tests' hanging scene body: 6 x 5 x 4 cells of 2 cm, top face pinned, raw constants
/// with volume damping (k_D, k_D,d, k_V, k_V,d, total mass).
Body hangingBox()
{
  Body body;
  body.mesh = makeTetBox(6, 5, 4, 0.02, Vec3(0, 0, 0.01));
  body.pinned.assign(body.mesh.points.size(), 0);
  for (std::size_t i = 0; i < body.mesh.points.size(); ++i)
  {
    body.pinned[i] = body.mesh.points[i].z() > 0.0899;
  }
  body.material.mode = MaterialMode::Raw;
  body.material.raw = { 0.2, 2e-5, 0.4, 8e-5, 1.0 };
  return body;
}

} // namespace

TEST(Simulation, TotalMassIsDensityTimesVolume)
{
  const Body body = boxBody();
  const MassSpringSimulation sim(body, SceneSettings{});
  EXPECT_NEAR(sim.totalMass(), body.material.physical.density * std::pow(0.15, 3), 1e-9);
}

TEST(Simulation, BodyFallsAndComesToRestOnTheFloor)
{
  SceneSettings scene;
  scene.floorEnabled = true;
  for (Integrator integrator : { Integrator::Midpoint, Integrator::Verlet, Integrator::EulerCromer })
  {
    scene.integrator = integrator;
    MassSpringSimulation sim(boxBody(), scene);
    sim.advance(3.0);
    double lowest = 1e9, fastest = 0.0;
    for (std::size_t i = 0; i < sim.positions().size(); ++i)
    {
      lowest = std::min(lowest, sim.positions()[i].z());
      fastest = std::max(fastest, sim.velocities()[i].norm());
    }
    EXPECT_GE(lowest, -1e-12) << integratorName(integrator);
    // It did land: the floor is a contact like any other and keeps the collision margin.
    EXPECT_LT(lowest, sim.collisionDetector()->margin() + 1e-3) << integratorName(integrator);
    EXPECT_LT(fastest, 0.05) << integratorName(integrator); // and settled
    // Sagging under its own weight, not crushed: rho g H / E = 1.6% axial strain at the bottom.
    // Measured: tet volume ratios in [0.9837, 1.0005], mean 0.9948-0.9950 (elasticity's mean
    // (1 - 2 nu) rho g H / 2E = 0.32% for uniaxial stress; the network compresses more).
    double mean = 0.0;
    const std::vector<double> ratios = sim.tetVolumeRatios();
    for (double ratio : ratios)
    {
      EXPECT_GT(ratio, 0.975) << integratorName(integrator);
      EXPECT_LT(ratio, 1.002) << integratorName(integrator);
      mean += ratio / double(ratios.size());
    }
    EXPECT_NEAR(mean, 0.9949, 0.002) << integratorName(integrator);
  }
}

TEST(Simulation, EulerCromerConservesMomentumOfAFreeSpinningBody)
{
  // No gravity, no floor: internal forces (with damping) are central and rotation invariant,
  // and symplectic Euler conserves sum m x_n x v_n exactly for such forces.
  Body body = boxBody();
  SceneSettings scene;
  scene.gravity = Vec3::Zero();
  MassSpringSimulation sim(body, scene);
  DynamicState spinning = sim.state();
  spinning.velocities = test::randomVectors(spinning.positions.size(), 0.5);
  for (std::size_t i = 0; i < spinning.positions.size(); ++i)
  {
    spinning.velocities[i] += Vec3(0, 0, 4.0).cross(spinning.positions[i] - Vec3(0.075, 0.075, 0.275));
  }
  sim.restoreState(spinning);
  const Vec3 p0 = linearMomentum(sim), l0 = angularMomentum(sim);
  sim.advance(0.3);
  EXPECT_LT((linearMomentum(sim) - p0).norm(), 1e-12 * (1 + p0.norm()) * double(sim.positions().size()));
  EXPECT_LT((angularMomentum(sim) - l0).norm(), 1e-12 * (1 + l0.norm()) * double(sim.positions().size()));
  EXPECT_GT(sim.stepCount(), 50u);
}

TEST(Simulation, PinnedPointsNeverMoveAndTheBodyHangs)
{
  Body body = boxBody(Vec3(0, 0, 1));
  body.pinned.assign(body.mesh.points.size(), 0);
  std::vector<std::size_t> top;
  for (std::size_t i = 0; i < body.mesh.points.size(); ++i)
  {
    if (body.mesh.points[i].z() > 1.149)
    {
      body.pinned[i] = 1;
      top.push_back(i);
    }
  }
  ASSERT_EQ(top.size(), 16u);
  MassSpringSimulation sim(body, SceneSettings{});
  sim.advance(1.0);
  for (std::size_t i : top)
  {
    EXPECT_EQ(sim.positions()[i], body.mesh.points[i]);
  }
  EXPECT_LT(sim.positions()[0].z(), body.mesh.points[0].z()); // the bottom sags
}

namespace
{
std::vector<Vec3> positionsAt(const Body& body, const SceneSettings& scene, double t)
{
  MassSpringSimulation sim(body, scene);
  sim.advance(t);
  return sim.positions();
}

/// Runs to t1, snapshots, runs on to t2, restores and runs to t3; expects the same bits as a
/// run to t1 and then t3.
void expectExactResume(const Body& body, const SceneSettings& scene, double t1 = 0.2,
  double t2 = 0.3, double t3 = 0.4)
{
  MassSpringSimulation straight(body, scene);
  straight.advance(t1);
  straight.advance(t3);
  MassSpringSimulation resumed(body, scene);
  resumed.advance(t1);
  const DynamicState snapshot = resumed.state();
  resumed.advance(t2);
  resumed.restoreState(snapshot);
  resumed.advance(t3);
  EXPECT_EQ(straight.positions(), resumed.positions());
  EXPECT_EQ(straight.velocities(), resumed.velocities());
  EXPECT_EQ(straight.stepCount(), resumed.stepCount());
}
} // namespace

TEST(Simulation, ResumingFromASnapshotReproducesTheRunExactly)
{
  // Falling onto the floor with the strain limit acting. Each stage is shown to act first: the
  // run without it ends elsewhere.
  SceneSettings scene;
  scene.floorEnabled = true;
  scene.strainLimit = 1.005;
  scene.integrator = Integrator::Verlet; // the limiter also corrects Verlet's velocities
  const std::vector<Vec3> reference = positionsAt(boxBody(), scene, 0.4);
  SceneSettings noFloor = scene;
  noFloor.floorEnabled = false;
  EXPECT_GT(test::maxDistance(positionsAt(boxBody(), noFloor, 0.4), reference), 0.1);
  SceneSettings noLimit = scene;
  noLimit.strainLimit = 0.0;
  EXPECT_GT(test::maxDistance(positionsAt(boxBody(), noLimit, 0.4), reference), 1e-4);
  expectExactResume(boxBody(), scene);
}

TEST(Simulation, ResumingAHangingBodyWithEveryStageReproducesTheRunExactly)
{
  // The GPU tests' hanging scene: pinned top face, strain limit 1.01, raw constants with volume
  // damping. Each acts (measured: the limiter moves points by 0.4-0.5 mm, volume damping by
  // 0.04-0.05 mm, the pins hold the body up by 49 mm), then resume.
  const Body body = hangingBox();
  SceneSettings scene;
  scene.strainLimit = 1.01;
  for (Integrator integrator : { Integrator::Verlet, Integrator::EulerCromer })
  {
    scene.integrator = integrator;
    const std::vector<Vec3> reference = positionsAt(body, scene, 0.1);
    Body free = body;
    free.pinned.clear();
    EXPECT_GT(test::maxDistance(positionsAt(free, scene, 0.1), reference), 0.03);
    SceneSettings noLimit = scene;
    noLimit.strainLimit = 0.0;
    EXPECT_GT(test::maxDistance(positionsAt(body, noLimit, 0.1), reference), 1e-4);
    Body noVolumeDamping = body;
    noVolumeDamping.material.raw.volumeDamping = 0.0;
    EXPECT_GT(test::maxDistance(positionsAt(noVolumeDamping, scene, 0.1), reference), 1e-5);
    expectExactResume(body, scene, 0.05, 0.08, 0.1);
  }
}

TEST(Simulation, StrainLimitHoldsDuringAFallOntoTheFloor)
{
  Body body = boxBody(Vec3(0, 0, 0.5));
  body.material.physical.youngsModulus = 2e3; // very soft: it would stretch a lot on impact
  SceneSettings scene;
  scene.floorEnabled = true;
  scene.strainLimit = 1.1;
  scene.strainLimitIterations = 30;
  MassSpringSimulation sim(body, scene);
  double worst = 0.0;
  for (int frame = 1; frame <= 20; ++frame)
  {
    sim.advance(0.05 * frame);
    worst = std::max(worst, maxStretchRatio(sim.topology(), sim.elementConstants(), sim.positions()));
  }
  EXPECT_LT(worst, 1.1 * 1.01);
}

TEST(Simulation, BadInputIsRefusedWithAClearMessage)
{
  auto messageOf = [](Body body, SceneSettings scene) -> std::string {
    try
    {
      MassSpringSimulation sim(std::move(body), scene);
    }
    catch (const InvalidInputError& error)
    {
      return error.what();
    }
    return "";
  };
  Body empty;
  EXPECT_NE(messageOf(empty, {}).find("empty"), std::string::npos);

  Body nan = boxBody();
  nan.mesh.points[5].y() = std::nan("");
  EXPECT_NE(messageOf(nan, {}).find("NaN"), std::string::npos);

  Body flat = boxBody();
  flat.mesh.tets.push_back({ 0, 1, 2, 3 }); // points 0..3 lie on one line of the box
  EXPECT_NE(messageOf(flat, {}).find("degenerate"), std::string::npos);

  Body inverted = boxBody();
  std::swap(inverted.mesh.tets[7][0], inverted.mesh.tets[7][1]);
  SceneSettings refuse;
  refuse.invertedTets = InvertedTetPolicy::Refuse;
  EXPECT_NE(messageOf(inverted, refuse).find("inverted"), std::string::npos);
  MassSpringSimulation reoriented(inverted, SceneSettings{});
  ASSERT_EQ(reoriented.warnings().size(), 1u);
  EXPECT_NE(reoriented.warnings()[0].find("re-oriented"), std::string::npos);
  for (double ratio : reoriented.tetVolumeRatios())
  {
    EXPECT_DOUBLE_EQ(ratio, 1.0);
  }

  Body soft = boxBody();
  soft.material.physical.youngsModulus = -5;
  EXPECT_NE(messageOf(soft, {}).find("YoungsModulus"), std::string::npos);
  soft.material.physical.youngsModulus = 1e5;
  soft.material.physical.poissonRatio = 0.5;
  EXPECT_NE(messageOf(soft, {}).find("PoissonRatio"), std::string::npos);

  SceneSettings badLimit;
  badLimit.strainLimit = 0.9;
  EXPECT_NE(messageOf(boxBody(), badLimit).find("StrainLimit"), std::string::npos);
}

TEST(Simulation, VerletVelocityStaysThePositionStepWhenTheLimiterMovesPoints)
{
  // Leapfrog stores v_{n+1/2} = (x_{n+1} - x_n) / h. The strain limiter moves points after the
  // drift, so it must move their velocities by the same amount over h, or Verlet's velocity
  // stops being its position step (without it, a 0.12 m body ends 2.2 mm away).
  const Body body = hangingBox();
  SceneSettings scene;
  scene.integrator = Integrator::Verlet;
  scene.strainLimit = 1.01;
  MassSpringSimulation sim(body, scene);
  const double h = sim.stepSize();
  std::size_t limited = 0;
  for (int step = 1; step <= 600; ++step)
  {
    const std::vector<Vec3> before = sim.positions();
    sim.advance(step * h);
    double worst = 0.0, speed = 0.0;
    for (std::size_t i = 0; i < before.size(); ++i)
    {
      worst = std::max(worst, (sim.velocities()[i] - (sim.positions()[i] - before[i]) / h).norm());
      speed = std::max(speed, sim.velocities()[i].norm());
    }
    ASSERT_LE(worst, 1e-9 * (speed + 1e-3)) << "step " << step;
    limited += maxStretchRatio(sim.topology(), sim.elementConstants(), sim.positions()) > 1.0099;
  }
  EXPECT_GT(limited, 100u); // the limiter acted in many of these steps
}

TEST(Simulation, PinnedPointsBelowTheFloorStayPinned)
{
  // A pinned point is fixed in space, even where the floor would push a free point out.
  Body body = boxBody(Vec3(0, 0, -0.01));
  body.pinned.assign(body.mesh.points.size(), 0);
  std::vector<std::size_t> pinned;
  for (std::size_t i = 0; i < body.mesh.points.size(); ++i)
  {
    if (body.mesh.points[i].z() < -0.009)
    {
      body.pinned[i] = 1;
      pinned.push_back(i);
    }
  }
  ASSERT_EQ(pinned.size(), 16u);
  SceneSettings scene;
  scene.floorEnabled = true;
  MassSpringSimulation sim(body, scene);
  sim.advance(0.1);
  for (std::size_t i : pinned)
  {
    EXPECT_EQ(sim.positions()[i], body.mesh.points[i]);
  }
  for (std::size_t i = 0; i < body.mesh.points.size(); ++i)
  {
    if (!body.pinned[i])
    {
      EXPECT_GE(sim.positions()[i].z(), 0.0); // the free points are above the floor
    }
  }
}
