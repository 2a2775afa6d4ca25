// Results must not depend on the number of threads: every parallel loop is a gather with a
// fixed summation order. Compared bit for bit, with a state hash as in Box2D's tests.
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"

#include <tbb/global_control.h>

#include <gtest/gtest.h>

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

std::uint64_t runWithThreads(std::size_t threads, Integrator integrator)
{
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  BodyDescription body;
  body.mesh = makeTetBox(14, 12, 12, 0.02, Vec3(0, 0, 0.05)); // > one grain of every loop
  SceneSettings scene;
  scene.integrator = integrator;
  scene.floorEnabled = true;
  scene.strainLimit = 1.05;
  MassSpringSimulation sim(body, scene);
  sim.advance(0.15);
  return hashState(sim.state());
}

} // namespace

TEST(Determinism, OneAndTwoThreadsGiveBitIdenticalStates)
{
  for (Integrator integrator : { Integrator::Midpoint, Integrator::Verlet })
  {
    EXPECT_EQ(runWithThreads(1, integrator), runWithThreads(2, integrator)) << integratorName(integrator);
  }
}
