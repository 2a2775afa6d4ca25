// Results must not depend on the number of threads: every parallel loop is a gather with a
// fixed summation order. Compared bit for bit, with a state hash as in Box2D's tests.
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"
#include "test_support.h"

#include <tbb/global_control.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

using namespace softbody;

namespace
{

std::uint64_t hashState(const DynamicState& state)
{
  std::uint64_t hash = 1469598103934665603ull; // FNV-1a over the raw bytes
  auto mix = [&](const std::vector<Vec3>& values) {
    const auto* bytes = reinterpret_cast<const unsigned char*>(values.data());
    for (std::size_t i = 0; i < values.size() * sizeof(Vec3); ++i)
    {
      hash = (hash ^ bytes[i]) * 1099511628211ull;
    }
  };
  mix(state.positions);
  mix(state.velocities);
  return hash;
}

SceneSettings busyScene(Integrator integrator)
{
  SceneSettings scene;
  scene.integrator = integrator;
  scene.floorEnabled = true;
  scene.strainLimit = 1.005; // acts on impact (1.05 never does)
  return scene;
}

DynamicState runWithThreads(std::size_t threads, const SceneSettings& scene)
{
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  Body body;
  body.mesh = makeTetBox(14, 12, 12, 0.02, Vec3(0, 0, 0.05)); // > one grain of every loop
  MassSpringSimulation sim(body, scene);
  sim.advance(0.15);
  return sim.state();
}

} // namespace

TEST(Determinism, OneAndTwoThreadsGiveBitIdenticalStates)
{
  for (Integrator integrator : { Integrator::Midpoint, Integrator::Verlet })
  {
    const DynamicState two = runWithThreads(2, busyScene(integrator));
    EXPECT_EQ(hashState(runWithThreads(1, busyScene(integrator))), hashState(two)) << integratorName(integrator);
    if (integrator == Integrator::Verlet)
    {
      // The stages compared are active: without the floor or the limiter the run ends elsewhere
      // (the body lands at ~0.1 s; the limiter corrects points on impact).
      SceneSettings noFloor = busyScene(integrator);
      noFloor.floorEnabled = false;
      EXPECT_GT(test::maxDistance(runWithThreads(2, noFloor).positions, two.positions), 1e-2);
      SceneSettings noLimit = busyScene(integrator);
      noLimit.strainLimit = 0.0;
      EXPECT_GT(test::maxDistance(runWithThreads(2, noLimit).positions, two.positions), 1e-5);
    }
  }
}
