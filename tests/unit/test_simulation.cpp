// Whole-simulation behaviour: landing on the floor, pins, conservation, input errors.
#include "softbody/common/errors.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"
#include "test_support.h"

#include <gtest/gtest.h>

using namespace softbody;

namespace
{

BodyDescription boxBody(const Vec3& origin = Vec3(0, 0, 0.2))
{
  BodyDescription body;
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

} // namespace

TEST(Simulation, TotalMassIsDensityTimesVolume)
{
  const BodyDescription body = boxBody();
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
    EXPECT_LT(lowest, 1e-3) << integratorName(integrator); // it did land
    EXPECT_LT(fastest, 0.05) << integratorName(integrator); // and settled
    for (double ratio : sim.tetVolumeRatios())
    {
      EXPECT_NEAR(ratio, 1.0, 0.1) << integratorName(integrator); // sagging, not crushed
    }
  }
}

TEST(Simulation, EulerCromerConservesMomentumOfAFreeSpinningBody)
{
  // No gravity, no floor: internal forces (with damping) are central and rotation invariant,
  // and symplectic Euler conserves sum m x_n x v_n exactly for such forces.
  BodyDescription body = boxBody();
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
  BodyDescription body = boxBody(Vec3(0, 0, 1));
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

TEST(Simulation, ResumingFromASnapshotReproducesTheRunExactly)
{
  SceneSettings scene;
  scene.floorEnabled = true;
  scene.strainLimit = 1.05;
  MassSpringSimulation straight(boxBody(), scene);
  straight.advance(0.2);
  straight.advance(0.4);
  MassSpringSimulation resumed(boxBody(), scene);
  resumed.advance(0.2);
  const DynamicState snapshot = resumed.state();
  resumed.advance(0.3);
  resumed.restoreState(snapshot);
  resumed.advance(0.4);
  EXPECT_EQ(straight.positions(), resumed.positions());
  EXPECT_EQ(straight.velocities(), resumed.velocities());
}

TEST(Simulation, StrainLimitHoldsDuringAFallOntoTheFloor)
{
  BodyDescription body = boxBody(Vec3(0, 0, 0.5));
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
  auto messageOf = [](BodyDescription body, SceneSettings scene) -> std::string {
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
  BodyDescription empty;
  EXPECT_NE(messageOf(empty, {}).find("empty"), std::string::npos);

  BodyDescription nan = boxBody();
  nan.mesh.points[5].y() = std::nan("");
  EXPECT_NE(messageOf(nan, {}).find("NaN"), std::string::npos);

  BodyDescription flat = boxBody();
  flat.mesh.tets.push_back({ 0, 1, 2, 3 }); // points 0..3 lie on one line of the box
  EXPECT_NE(messageOf(flat, {}).find("degenerate"), std::string::npos);

  BodyDescription inverted = boxBody();
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

  BodyDescription soft = boxBody();
  soft.material.physical.youngsModulus = -5;
  EXPECT_NE(messageOf(soft, {}).find("YoungsModulus"), std::string::npos);
  soft.material.physical.youngsModulus = 1e5;
  soft.material.physical.poissonRatio = 0.5;
  EXPECT_NE(messageOf(soft, {}).find("PoissonRatio"), std::string::npos);

  SceneSettings badLimit;
  badLimit.strainLimit = 0.9;
  EXPECT_NE(messageOf(boxBody(), badLimit).find("StrainLimit"), std::string::npos);
}
