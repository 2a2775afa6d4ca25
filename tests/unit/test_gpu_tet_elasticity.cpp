// Stable Neo-Hookean finite-element tets on the GPU against core's CPU stepper: the same states
// (bitwise on llvmpipe) after 1,500 steps for every explicit integrator, with the floor (default friction),
// the strain limiter and viscous damping acting; Corotated falls back with its reason. Skipped
// where no EGL / OpenGL 4.3 context exists.
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/material/tet_elastic_forces.h"
#include "softbody/mesh/mesh_generators.h"
#include "gpu_test_support.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

using namespace softbody;

namespace
{

/// 6 x 5 x 4 cells of 2 cm (720 tets) lifted 1 cm, falling onto the floor: E = 1e5 Pa,
/// nu = 0.3 (below the network's 0.25 floor, so this is the continuum's own Poisson ratio).
Body neoHookeanBody(MaterialModel model = MaterialModel::StableNeoHookean)
{
  Body body;
  body.mesh = makeTetBox(6, 5, 4, 0.02, Vec3(0.0, 0.0, 0.01));
  body.material.model = model;
  body.material.physical.poissonRatio = 0.3;
  return body;
}

SceneSettings landingScene(Integrator integrator)
{
  SceneSettings scene;
  scene.integrator = integrator;
  scene.floorEnabled = true;
  scene.strainLimit = 1.05;
  scene.collisions.staticFriction = 0.3; // the filter's defaults
  scene.collisions.dynamicFriction = 0.3;
  return scene;
}

class GpuTetElasticity : public ::testing::TestWithParam<Integrator>
{
};

} // namespace

TEST_P(GpuTetElasticity, SameStatesAsTheCpuThroughTheLanding)
{
  const Body body = neoHookeanBody();
  const SceneSettings scene = landingScene(GetParam());
  MAKE_GPU_OR_SKIP(gpu, body, scene);
  MassSpringSimulation cpu(body, scene);
  EXPECT_EQ(gpu->stepSize(), cpu.stepSize());
  const double size = 0.12;
  for (double t : { 0.02, 0.04, 0.06 })
  {
    gpu->advance(t);
    cpu.advance(t);
    ASSERT_EQ(gpu->stepCount(), cpu.stepCount());
    const double dx = test::maxDistance(gpu->positions(), cpu.positions());
    const double dv = test::maxDistance(gpu->velocities(), cpu.velocities());
    std::cout << integratorName(GetParam()) << " t = " << t << " s, " << cpu.stepCount()
              << " steps: max |dx| / size = " << dx / size << ", max |dv| = " << dv << " m/s"
              << (test::bitwiseEqual(gpu->positions(), cpu.positions()) ? " (bitwise equal)" : "") << "\n";
    if (test::softwareRenderer(*gpu))
    {
      // The shader sums in Eigen's SSE2 order (tet_elastic_forces.comp): nothing rounds apart.
      EXPECT_TRUE(test::bitwiseEqual(gpu->positions(), cpu.positions()));
    }
    const test::GpuTolerance bound = t < 0.03 ? test::GpuTolerance{ test::kGpuRelativeTolerance, 1e-9 }
                                              : test::afterThresholdStages(*gpu);
    EXPECT_LE(dx / size, bound.position) << gpu->glRenderer();
    EXPECT_LE(dv, bound.velocity) << gpu->glRenderer();
  }
  // The comparison is of an elastic landing: the body reached the floor and deformed (its
  // elastic energy is far from zero), and the energy the host computes from the GPU's state is
  // the CPU's.
  const Vec3 lowest = *std::min_element(cpu.positions().begin(), cpu.positions().end(),
    [](const Vec3& a, const Vec3& b) { return a.z() < b.z(); });
  EXPECT_LT(std::abs(lowest.z()), 0.005);
  EXPECT_GT(cpu.elasticEnergy(), 1e-6);
  EXPECT_NEAR(gpu->elasticEnergy(), cpu.elasticEnergy(), 1e-6 * cpu.elasticEnergy());
  EXPECT_EQ(gpu->stressField().vonMises.size(), body.mesh.tets.size());
  if (GetParam() != Integrator::EulerCromer)
  {
    return; // the checks below are of the scene, not of the integrator
  }
  // Damping acts in what is compared: the undamped landing ends elsewhere.
  Body undamped = body;
  undamped.material.physical.dampingTime = 0.0;
  MassSpringSimulation bouncy(undamped, scene);
  bouncy.advance(0.06);
  EXPECT_GT(test::maxDistance(bouncy.positions(), cpu.positions()) / size, 1e-5);
}

INSTANTIATE_TEST_SUITE_P(AllIntegrators, GpuTetElasticity,
  ::testing::Values(Integrator::Euler, Integrator::Midpoint, Integrator::Verlet, Integrator::EulerCromer),
  [](const ::testing::TestParamInfo<Integrator>& param) {
    std::string name = integratorName(param.param);
    name.erase(std::remove(name.begin(), name.end(), '-'), name.end());
    return name;
  });

TEST(GpuTetElasticity, CorotatedIsLeftToTheCpuWithItsReason)
{
  std::string whyNot;
  const auto gpu = gpu::tryCreateGpuMassSpring(
    neoHookeanBody(MaterialModel::Corotated), landingScene(Integrator::Verlet), whyNot);
  EXPECT_EQ(gpu, nullptr);
  EXPECT_NE(whyNot.find("Corotated"), std::string::npos) << whyNot;
}
