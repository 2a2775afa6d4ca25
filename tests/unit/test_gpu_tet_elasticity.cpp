// Finite-element tets on the GPU against core's CPU stepper, for every explicit integrator, with
// the floor (default friction), the strain limiter and viscous damping acting: Stable
// Neo-Hookean bitwise the CPU's on llvmpipe after 1,500 steps, Corotated to rounding (its
// rotation comes from another SVD algorithm, tet_elastic_forces.comp); and Corotated's stress
// for deformations far from rest (inverted, flat, repeated singular values) against the CPU's.
// Skipped where no EGL / OpenGL 4.3 context exists.
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/material/tet_elastic_forces.h"
#include "softbody/mesh/mesh_generators.h"
#include "gpu_test_support.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <tuple>

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

using test::ModelAndIntegrator;

class GpuTetElasticity : public ::testing::TestWithParam<ModelAndIntegrator>
{
};

} // namespace

TEST_P(GpuTetElasticity, SameStatesAsTheCpuThroughTheLanding)
{
  const auto [model, integrator] = GetParam();
  const Body body = neoHookeanBody(model);
  const SceneSettings scene = landingScene(integrator);
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
    std::cout << materialModelName(model) << ", " << integratorName(integrator) << " t = " << t << " s, " << cpu.stepCount()
              << " steps: max |dx| / size = " << dx / size << ", max |dv| = " << dv << " m/s"
              << (test::bitwiseEqual(gpu->positions(), cpu.positions()) ? " (bitwise equal)" : "") << "\n";
    if (test::softwareRenderer(*gpu) && model == MaterialModel::StableNeoHookean)
    {
      // The shader sums in Eigen's SSE2 order (tet_elastic_forces.comp): nothing rounds apart.
      EXPECT_TRUE(test::bitwiseEqual(gpu->positions(), cpu.positions()));
    }
    // Corotated's rotation rounds apart from the CPU's, by rounding only: the same bounds hold.
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
  if (integrator != Integrator::EulerCromer)
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

INSTANTIATE_TEST_SUITE_P(ModelsAndIntegrators, GpuTetElasticity,
  ::testing::Combine(::testing::Values(MaterialModel::StableNeoHookean, MaterialModel::Corotated),
    ::testing::Values(Integrator::Euler, Integrator::Midpoint, Integrator::Verlet, Integrator::EulerCromer)),
  test::modelAndIntegratorName);

namespace
{

/// Deformation gradients a rotation-finding SVD finds hardest, then random ones: a pure
/// rotation (no stress), repeated and nearly repeated singular values, a flat and a nearly
/// flat tet, inverted ones, and random F = R1 diag(s) R2 with s in [-0.5, 2] (a quarter inverted).
/// Not an inverted F whose two smallest singular values have one magnitude (s = (1, 1, -1)):
/// which direction of their plane is reflected is free there, so R, and the stress, are not
/// unique (the two sides pick different, equally valid ones).
std::vector<Mat3> hardDeformations(std::size_t randomCount)
{
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto rotation = [&] {
    const Vec3 axis = Vec3(unit(random), unit(random), unit(random)).normalized();
    return Eigen::AngleAxisd(3.14159 * unit(random), axis).toRotationMatrix();
  };
  std::vector<Vec3> singularValues = { { 1.0, 1.0, 1.0 }, { 1.2, 1.2, 0.7 }, { 1.3, 0.9, 0.9 },
    { 1.1, 1.1 + 1e-9, 0.8 }, { 1.2, 0.8, 0.0 }, { 1.2, 0.8, 1e-7 }, { 1.5, 1e-6, 1e-7 },
    { 1.1, 0.9, -0.3 }, { 1.0, 1.0, -0.5 }, { 0.6, 0.5, -0.4 } };
  std::vector<Mat3> deformations;
  for (const Vec3& s : singularValues)
  {
    deformations.push_back(rotation() * s.asDiagonal() * rotation());
  }
  deformations.push_back(Mat3::Identity()); // the axes themselves: Jacobi starts orthogonal
  std::uniform_real_distribution<double> stretch(0.2, 2.0);
  for (std::size_t k = 0; k < randomCount; ++k)
  {
    Vec3 s(stretch(random), stretch(random), stretch(random));
    if (k % 4 == 0)
    {
      s.z() = -0.5 * std::abs(unit(random)); // inverted
    }
    deformations.push_back(rotation() * s.asDiagonal() * rotation());
  }
  return deformations;
}

/// The condition number of F's rotation: 1 / min |s_i + s_j| over F's signed singular values.
double rotationCondition(const Mat3& f)
{
  // Singular values from the eigenvalues of F^T F, signed by det F: accurate enough for a
  // condition number, and free of JacobiSVD's spurious uninitialized-use warning here.
  const Vec3 squares = Eigen::SelfAdjointEigenSolver<Mat3>(f.transpose() * f).eigenvalues();
  Vec3 s = squares.cwiseMax(0.0).cwiseSqrt(); // ascending
  if (f.determinant() < 0.0)
  {
    s(0) = -s(0);
  }
  const double gap = std::min({ std::abs(s(0) + s(1)), std::abs(s(0) + s(2)), std::abs(s(1) + s(2)) });
  return std::max(1.0, 1.0 / gap);
}

} // namespace

TEST(GpuTetElasticity, CorotatedStressFarFromRestIsTheCpus)
{
  // One loose tet per deformation, placed deformed by restoreState; one explicit Euler step
  // from rest velocities makes v = h f / m, so the velocities compare the corner forces.
  const std::vector<Mat3> deformations = hardDeformations(300);
  Body body;
  body.material.model = MaterialModel::Corotated;
  body.material.physical.poissonRatio = 0.3;
  body.material.physical.dampingTime = 0.0;
  const std::array<Vec3, 4> corners = { Vec3(0, 0, 0), Vec3(0.05, 0, 0), Vec3(0, 0.05, 0), Vec3(0, 0, 0.05) };
  DynamicState deformed;
  for (std::size_t k = 0; k < deformations.size(); ++k)
  {
    const Vec3 origin(0.2 * static_cast<double>(k), 0.0, 0.0);
    const auto first = static_cast<std::int32_t>(body.mesh.points.size());
    body.mesh.tets.push_back({ first, first + 1, first + 2, first + 3 });
    for (const Vec3& corner : corners)
    {
      body.mesh.points.push_back(origin + corner);
      deformed.positions.push_back(origin + deformations[k] * corner);
      deformed.velocities.push_back(Vec3::Zero());
    }
  }
  SceneSettings scene;
  scene.integrator = Integrator::Euler;
  scene.gravity = Vec3::Zero();
  scene.floorEnabled = false;
  MAKE_GPU_OR_SKIP(gpu, body, scene);
  MassSpringSimulation cpu(body, scene);
  gpu->restoreState(deformed);
  cpu.restoreState(deformed);
  gpu->advance(cpu.stepSize());
  cpu.advance(cpu.stepSize());
  ASSERT_EQ(cpu.stepCount(), 1u);
  ASSERT_EQ(gpu->stepCount(), 1u);
  double largest = 0.0;
  for (const Vec3& v : cpu.velocities())
  {
    largest = std::max(largest, v.norm());
  }
  ASSERT_GT(largest, 0.0);
  // F's rotation is as well defined as its singular values are apart: rounding F by eps moves
  // R by about eps / min |s_i + s_j| (signed s, the polar factor's condition), so a nearly
  // collapsed tet (s = (1.5, 1e-6, 1e-7)) has R, and its stress, only to ~1e-10 from either
  // side.
  std::size_t worstTet = 0;
  double worst = 0.0; // the difference over its bound
  for (std::size_t i = 0; i < cpu.velocities().size(); ++i)
  {
    const double difference = (gpu->velocities()[i] - cpu.velocities()[i]).norm() / largest;
    const double ratio = difference / (1e-14 * rotationCondition(deformations[i / 4]));
    if (ratio > worst)
    {
      worst = ratio;
      worstTet = i / 4;
    }
  }
  std::cout << deformations.size() << " deformations: largest |f_gpu - f_cpu| / max |f| is "
            << worst << " x 1e-14 x the rotation's condition number (tet " << worstTet << ")\n";
  EXPECT_LE(worst, 1.0) << "tet " << worstTet << ", F =\n" << deformations[worstTet];
  // The pure rotation has no stress: both sides agree it is zero, not merely each other.
  EXPECT_LE(cpu.velocities()[0].norm() / largest, 1e-12);
}
