// The GPU stepper against core's CPU stepper: same set-up, same states after N steps within a
// stated tolerance, for every integrator; bitwise reproducible across runs; the frame-cache
// contract (state / restoreState). Skipped (GTEST_SKIP, reported as skipped by CTest) where
// no EGL/OpenGL 4.3 context can be made.
#include "softbody/common/errors.h"
#include "softbody/gpu/mass_spring_gpu_simulation.h"
#include "softbody/massspring/mass_spring_plan.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"
#include "gpu_test_support.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>

using namespace softbody;

namespace
{

using test::afterThresholdStages;
using test::kGpuRelativeTolerance;
using Tolerance = test::GpuTolerance;

Body smallBody(bool pinTop = false)
{
  Body body;
  // 6 x 5 x 4 cells: 720 tets, ~1k edges; lifted so that it falls onto the floor.
  body.mesh = makeTetBox(6, 5, 4, 0.02, Vec3(0.0, 0.0, 0.01));
  if (pinTop)
  {
    body.pinned.assign(body.mesh.points.size(), 0);
    for (std::size_t i = 0; i < body.mesh.points.size(); ++i)
    {
      body.pinned[i] = body.mesh.points[i].z() > 0.0899 ? 1 : 0;
    }
  }
  return body;
}

SceneSettings busyScene(Integrator integrator)
{
  // Every stage on: volume term (Poisson 0.3), strain limit and floor contact with the
  // filter's default friction (StaticFriction = DynamicFriction = 0.3, Restitution 0). The
  // limit is low enough to act: without it the falling body stretches its springs to ~1.023
  // on impact (a limit of 1.05 never fires).
  SceneSettings scene;
  scene.integrator = integrator;
  scene.floorEnabled = true;
  scene.strainLimit = 1.005;
  scene.collisions.staticFriction = 0.3;
  scene.collisions.dynamicFriction = 0.3;
  return scene;
}

/// The hanging scene: top face pinned, no floor, raw constants with volume damping (the
/// physical material cannot switch volume damping off alone), strain limit acting on the
/// stretched top layer (without it the springs reach 1.018 by 0.1 s).
Body hangingBody()
{
  Body body = smallBody(/*pinTop=*/true);
  body.material.mode = MaterialMode::Raw;
  body.material.raw = { 0.2, 2e-5, 0.4, 8e-5, 1.0 }; // k_D, k_D,d, k_V, k_V,d [J, J s], mass [kg]
  return body;
}

SceneSettings hangingScene(Integrator integrator)
{
  SceneSettings scene;
  scene.integrator = integrator;
  scene.strainLimit = 1.01;
  return scene;
}

/// CPU positions after `endTime`.
std::vector<Vec3> cpuPositions(const Body& body, const SceneSettings& scene, double endTime)
{
  MassSpringSimulation simulation(body, scene);
  simulation.advance(endTime);
  return simulation.positions();
}

class GpuAgainstCpu : public ::testing::TestWithParam<Integrator>
{
};

} // namespace

TEST_P(GpuAgainstCpu, SameStatesAfterManyStepsWithEveryStage)
{
  const Body body = smallBody();
  const SceneSettings scene = busyScene(GetParam());
  MAKE_GPU_OR_SKIP(gpuSimulation, body, scene);
  MassSpringSimulation cpuSimulation(body, scene);

  // Same set-up: core's code on both sides.
  EXPECT_EQ(gpuSimulation->stepSize(), cpuSimulation.stepSize());
  EXPECT_EQ(gpuSimulation->estimatedStableStep(), cpuSimulation.estimatedStableStep());
  EXPECT_EQ(gpuSimulation->totalMass(), cpuSimulation.totalMass());
  EXPECT_EQ(gpuSimulation->warnings(), cpuSimulation.warnings());

  // Three frames of 0.02 s: a few hundred steps; the body hits the floor and bounces.
  const double size = 0.12;
  for (double t : { 0.02, 0.04, 0.06 })
  {
    gpuSimulation->advance(t);
    cpuSimulation.advance(t);
    ASSERT_EQ(gpuSimulation->stepCount(), cpuSimulation.stepCount());
    ASSERT_EQ(gpuSimulation->time(), cpuSimulation.time());
    const double dx = test::maxDistance(gpuSimulation->positions(), cpuSimulation.positions());
    const double dv = test::maxDistance(gpuSimulation->velocities(), cpuSimulation.velocities());
    std::cout << integratorName(GetParam()) << " t = " << t << " s, " << cpuSimulation.stepCount()
              << " steps: max |dx| / size = " << dx / size << ", max |dv| = " << dv << " m/s"
              << (test::bitwiseEqual(gpuSimulation->positions(), cpuSimulation.positions()) ? " (bitwise equal)" : "")
              << "\n";
    // The first frame is free fall: smooth, so tight on every GPU.
    const Tolerance bound =
      t < 0.03 ? Tolerance{ kGpuRelativeTolerance, 1e-9 } : afterThresholdStages(*gpuSimulation);
    EXPECT_LE(dx / size, bound.position) << gpuSimulation->glRenderer();
    EXPECT_LE(dv, bound.velocity) << gpuSimulation->glRenderer();
  }
  // The body moved (the comparison is not between two resting bodies).
  EXPECT_GT(test::maxDistance(cpuSimulation.positions(), cpuSimulation.restPositions()), 1e-3);
  // Every stage compared is active: the same run without it ends elsewhere, by far more than
  // the tolerance (a GPU bug in that stage would show).
  SceneSettings noLimit = scene;
  noLimit.strainLimit = 0.0;
  MassSpringSimulation unlimited(body, noLimit);
  double stretched = 0.0;
  for (double t : { 0.02, 0.04, 0.06 })
  {
    unlimited.advance(t);
    stretched = std::max(stretched, maxStretchRatio(unlimited.topology(), unlimited.elementConstants(), unlimited.positions()));
  }
  EXPECT_GT(stretched, scene.strainLimit * 1.005) << "the limiter would not act";
  EXPECT_GT(test::maxDistance(unlimited.positions(), cpuSimulation.positions()) / size, 1e-5);
  SceneSettings noFloor = scene;
  noFloor.floorEnabled = false;
  EXPECT_GT(test::maxDistance(cpuPositions(body, noFloor, 0.06), cpuSimulation.positions()) / size, 1e-3);
  SceneSettings noFriction = scene;
  noFriction.collisions.staticFriction = noFriction.collisions.dynamicFriction = 0.0;
  const double frictionMoves = test::maxDistance(cpuPositions(body, noFriction, 0.06), cpuSimulation.positions()) / size;
  std::cout << "friction moves points by " << frictionMoves << " of the size\n";
  EXPECT_GT(frictionMoves, 1e-5);
  const std::vector<double> gpuRatios = gpuSimulation->tetVolumeRatios();
  const std::vector<double> cpuRatios = cpuSimulation.tetVolumeRatios();
  ASSERT_EQ(gpuRatios.size(), cpuRatios.size());
  // A position bound b (of the 0.12 m size) moves a 0.02 m cell's volume by up to ~3 * 6 b.
  const double ratioBound = std::max(1e-6, 18.0 * afterThresholdStages(*gpuSimulation).position);
  for (std::size_t t = 0; t < gpuRatios.size(); ++t)
  {
    ASSERT_NEAR(gpuRatios[t], cpuRatios[t], ratioBound);
  }
}

TEST(MassSpring, SameStatesAsTheCpuWhenHangingFromPinsWithTheLimiterActing)
{
  // Verlet (whose velocity the limiter corrects) and Euler-Cromer; Midpoint and Euler need far
  // smaller steps with these low damping ratios, and are compared in the falling scene.
  for (Integrator integrator : { Integrator::Verlet, Integrator::EulerCromer })
  {
    const Body body = hangingBody();
    const SceneSettings scene = hangingScene(integrator);
    MAKE_GPU_OR_SKIP(gpuSimulation, body, scene);
    MassSpringSimulation cpuSimulation(body, scene);
    const double size = 0.12, endTime = 0.1;
    gpuSimulation->advance(endTime);
    cpuSimulation.advance(endTime);
    ASSERT_EQ(gpuSimulation->stepCount(), cpuSimulation.stepCount());
    const double dx = test::maxDistance(gpuSimulation->positions(), cpuSimulation.positions());
    std::cout << integratorName(integrator) << " hanging, " << cpuSimulation.stepCount()
              << " steps: max |dx| / size = " << dx / size << "\n";
    const Tolerance bound = afterThresholdStages(*gpuSimulation);
    EXPECT_LE(dx / size, bound.position) << gpuSimulation->glRenderer();
    EXPECT_LE(test::maxDistance(gpuSimulation->velocities(), cpuSimulation.velocities()), bound.velocity)
      << gpuSimulation->glRenderer();
    for (std::size_t i = 0; i < body.pinned.size(); ++i)
    {
      if (body.pinned[i])
      {
        ASSERT_EQ(gpuSimulation->positions()[i], body.mesh.points[i]);
      }
    }

    // Each stage acts, by far more than the tolerance (measured: the limiter moves points by
    // 0.4-0.5 mm, volume damping by 0.04-0.05 mm; without pins the body falls 49 mm).
    Body free = body;
    free.pinned.clear();
    EXPECT_GT(test::maxDistance(cpuPositions(free, scene, endTime), cpuSimulation.positions()), 0.03);
    SceneSettings noLimit = scene;
    noLimit.strainLimit = 0.0;
    MassSpringSimulation unlimited(body, noLimit);
    unlimited.advance(endTime);
    EXPECT_GT(maxStretchRatio(unlimited.topology(), unlimited.elementConstants(), unlimited.positions()),
      scene.strainLimit * 1.005);
    EXPECT_GT(test::maxDistance(unlimited.positions(), cpuSimulation.positions()), 1e-4);
    Body noVolumeDamping = body;
    noVolumeDamping.material.raw.volumeDamping = 0.0;
    EXPECT_GT(test::maxDistance(cpuPositions(noVolumeDamping, scene, endTime), cpuSimulation.positions()), 1e-5);
  }
}

TEST(MassSpring, VerletAcrossStepSizeChangesAsOnTheCpu)
{
  // Free fall (floor off) with intervals that change the step: 1 ms, 0.9875 ms, 0.8333 ms,
  // 1 ms. Leapfrog with the mean of the previous and current step is exact in free fall; the
  // GPU kicks the first step of each batch by that mean too.
  Body body = smallBody();
  body.material.physical.youngsModulus = 1e3; // 1 ms is then a stable step (5 ms is the limit)
  SceneSettings scene;
  scene.integrator = Integrator::Verlet;
  scene.timeStep = 1e-3;
  MAKE_GPU_OR_SKIP(gpuSimulation, body, scene);
  MassSpringSimulation cpuSimulation(body, scene);
  for (double t : { 0.02, 0.0437, 0.0462, 0.0662 })
  {
    gpuSimulation->advance(t);
    cpuSimulation.advance(t);
    for (std::size_t i = 0; i < body.mesh.points.size(); ++i)
    {
      const Vec3 exact = body.mesh.points[i] + Vec3(0, 0, 0.5 * scene.gravity.z() * t * t);
      ASSERT_LT((gpuSimulation->positions()[i] - exact).norm(), 1e-12)
        << "t = " << t << ", CPU off by " << (cpuSimulation.positions()[i] - exact).norm();
    }
    EXPECT_LE(test::maxDistance(gpuSimulation->positions(), cpuSimulation.positions()), 1e-12);
  }
  EXPECT_EQ(gpuSimulation->stepCount(), 20u + 24u + 3u + 20u);
}

INSTANTIATE_TEST_SUITE_P(AllIntegrators, GpuAgainstCpu,
  ::testing::Values(Integrator::Euler, Integrator::Midpoint, Integrator::Verlet,
    Integrator::EulerCromer),
  [](const ::testing::TestParamInfo<Integrator>& param) {
    std::string name = integratorName(param.param);
    name.erase(std::remove(name.begin(), name.end(), '-'), name.end());
    return name;
  });

TEST(MassSpring, TwoRunsAreBitwiseEqual)
{
  const Body body = smallBody();
  const SceneSettings scene = busyScene(Integrator::Midpoint);
  MAKE_GPU_OR_SKIP(first, body, scene);
  MAKE_GPU_OR_SKIP(second, body, scene);
  first->advance(0.05);
  second->advance(0.05);
  EXPECT_TRUE(test::bitwiseEqual(first->positions(), second->positions()));
  EXPECT_TRUE(test::bitwiseEqual(first->velocities(), second->velocities()));
}

TEST(MassSpring, DownloadingBetweenFramesChangesNothing)
{
  const Body body = smallBody();
  const SceneSettings scene = busyScene(Integrator::Verlet);
  MAKE_GPU_OR_SKIP(framed, body, scene);
  MAKE_GPU_OR_SKIP(straight, body, scene);
  for (int frame = 1; frame <= 5; ++frame)
  {
    framed->advance(0.01 * frame);
    (void)framed->state(); // downloads: the GPU state is not touched
    straight->advance(0.01 * frame);
  }
  EXPECT_EQ(framed->stepCount(), straight->stepCount());
  EXPECT_TRUE(test::bitwiseEqual(framed->positions(), straight->positions()));
}

TEST(MassSpring, ResumingFromASnapshotReproducesTheRunExactly)
{
  const Body body = smallBody();
  const SceneSettings scene = busyScene(Integrator::EulerCromer);
  MAKE_GPU_OR_SKIP(simulation, body, scene);
  simulation->advance(0.02);
  const DynamicState snapshot = simulation->state();
  simulation->advance(0.04);
  const DynamicState later = simulation->state();

  simulation->restoreState(snapshot);
  EXPECT_EQ(simulation->time(), snapshot.time);
  EXPECT_TRUE(test::bitwiseEqual(simulation->positions(), snapshot.positions));
  simulation->advance(0.04);
  EXPECT_EQ(simulation->stepCount(), later.stepCount);
  EXPECT_TRUE(test::bitwiseEqual(simulation->positions(), later.positions));
  EXPECT_TRUE(test::bitwiseEqual(simulation->velocities(), later.velocities));

  DynamicState wrong = snapshot;
  wrong.positions.pop_back();
  EXPECT_THROW(simulation->restoreState(wrong), InvalidInputError);
}

TEST(MassSpring, PinnedPointsNeverMove)
{
  const Body body = smallBody(/*pinTop=*/true);
  SceneSettings scene = busyScene(Integrator::EulerCromer);
  scene.floorEnabled = false;
  MAKE_GPU_OR_SKIP(simulation, body, scene);
  simulation->advance(0.05);
  std::size_t pinned = 0;
  for (std::size_t i = 0; i < body.pinned.size(); ++i)
  {
    if (body.pinned[i])
    {
      ++pinned;
      ASSERT_EQ(simulation->positions()[i], body.mesh.points[i]);
    }
  }
  EXPECT_GT(pinned, 0u);
  EXPECT_GT(test::maxDistance(simulation->positions(), simulation->restPositions()), 1e-4); // it sags
}

TEST(MassSpring, PlanNamesTheSameStagesAsTheCpu)
{
  const Body body = smallBody();
  const SceneSettings scene = busyScene(Integrator::Midpoint);
  MAKE_GPU_OR_SKIP(gpuSimulation, body, scene);
  MassSpringSimulation cpuSimulation(body, scene);
  const auto start = std::chrono::steady_clock::now();
  gpuSimulation->advance(0.01);
  (void)gpuSimulation->positions(); // a frame's download: the transfers stage
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // The GPU has its own floor pass where the CPU detects contacts (the floor among them).
  std::vector<Stage> expected = planMassSpring(prepareMassSpring(body, scene)).stages();
  expected.push_back(Stage::Transfers);
  EXPECT_EQ(gpuSimulation->plan(), expected);
  std::vector<Stage> cpuWithFloorPass = cpuSimulation.plan();
  std::replace(cpuWithFloorPass.begin(), cpuWithFloorPass.end(), Stage::CollisionDetect, Stage::Floor);
  cpuWithFloorPass.erase(std::remove(cpuWithFloorPass.begin(), cpuWithFloorPass.end(), Stage::Contacts),
    cpuWithFloorPass.end());
  cpuWithFloorPass.push_back(Stage::Transfers);
  EXPECT_EQ(gpuSimulation->plan(), cpuWithFloorPass);
  // Every planned stage ran and was timed; together they took no longer than the advance and
  // the download.
  double total = 0.0;
  for (const StageTiming& timing : gpuSimulation->stageTimings())
  {
    EXPECT_GT(timing.seconds, 0.0) << timing.label;
    total += timing.seconds;
  }
  EXPECT_LE(total, wall);
  EXPECT_FALSE(gpuSimulation->glRenderer().empty());
}

TEST(MassSpring, BlowingUpThrowsWithTheTimeOfDivergence)
{
  const Body body = smallBody();
  SceneSettings scene = busyScene(Integrator::EulerCromer);
  scene.strainLimit = 0.0;
  scene.timeStep = 2e-3; // far above the stable step
  MAKE_GPU_OR_SKIP(simulation, body, scene);
  MassSpringSimulation cpuSimulation(body, scene);
  double gpuTime = -1.0, cpuTime = -2.0;
  try
  {
    simulation->advance(1.0);
  }
  catch (const SimulationDivergedError& error)
  {
    gpuTime = error.time;
  }
  try
  {
    cpuSimulation.advance(1.0);
  }
  catch (const SimulationDivergedError& error)
  {
    cpuTime = error.time;
  }
  EXPECT_GT(gpuTime, 0.0);
  EXPECT_EQ(gpuTime, cpuTime); // detected at the same check
}

TEST(MassSpring, InvalidInputIsRefusedAsOnTheCpu)
{
  Body body = smallBody();
  body.pinned.assign(3, 1);
  std::string whyNot;
  EXPECT_THROW(gpu::tryCreateGpuMassSpring(body, busyScene(Integrator::Euler), whyNot),
    InvalidInputError);
}
