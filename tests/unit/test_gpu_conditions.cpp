// Conditions on the GPU against core's CPU stepper: a bar clamped at one end (Fixed), on a
// roller at the other (x held), twisted and pulled by a Prescribed motion of a middle slice
// (sinusoid), and loaded by a Force spread by mass (ramp), for every explicit integrator, with
// the Spring Network and Stable Neo-Hookean: the same states (bitwise on llvmpipe: the loads and
// targets are core's values, summed where core sums them), the same support reactions, and
// the same run after the loads change while it plays. Pressure and Pull fall back to the CPU
// naming the condition. Skipped where no EGL / OpenGL 4.3 context exists.
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"
#include "gpu_test_support.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <string>
#include <tuple>

using namespace softbody;

namespace
{

constexpr double kLength = 0.2; // 10 x 2 x 2 cells of 2 cm along x

std::vector<std::int32_t> pointsWhere(const TetMesh& mesh, double x)
{
  std::vector<std::int32_t> set;
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
  {
    if (std::abs(mesh.points[i].x() - x) < 1e-9)
    {
      set.push_back(static_cast<std::int32_t>(i));
    }
  }
  return set;
}

Body loadedBar(MaterialModel model)
{
  Body body;
  body.mesh = makeTetBox(10, 2, 2, 0.02);
  body.material.model = model;
  body.material.physical.poissonRatio = 0.3;

  Condition clamp;
  clamp.name = "clamp";
  clamp.points = pointsWhere(body.mesh, 0.0);

  Condition roller;
  roller.name = "roller";
  roller.points = pointsWhere(body.mesh, kLength);
  roller.heldAxes = { true, false, false };

  Condition drive;
  drive.name = "drive";
  drive.kind = ConditionKind::Prescribed;
  drive.points = pointsWhere(body.mesh, 0.1);
  drive.translation = Vec3(0.0, 0.0, 0.004);
  drive.rotationAxis = Vec3(1.0, 0.0, 0.0);
  drive.rotationCenter = Vec3(0.1, 0.02, 0.02);
  drive.rotationAngle = 0.2;
  drive.profile.shape = TimeProfileShape::Sinusoid;
  drive.profile.duration = 0.05;

  Condition load;
  load.name = "load";
  load.kind = ConditionKind::Force;
  load.points = pointsWhere(body.mesh, 0.16);
  load.force = Vec3(0.0, 2.0, -3.0);
  load.profile.shape = TimeProfileShape::Ramp;
  load.profile.duration = 0.02;

  body.conditions = { clamp, roller, drive, load };
  return body;
}

using test::ModelAndIntegrator;

class GpuConditions : public ::testing::TestWithParam<ModelAndIntegrator>
{
};

double largestReaction(const ConditionReadout& readout)
{
  double largest = 0.0;
  for (const Vec3& r : readout.reactions)
  {
    largest = std::max(largest, r.norm());
  }
  return largest;
}

} // namespace

TEST_P(GpuConditions, SameStatesAndReactionsAsTheCpu)
{
  const auto [model, integrator] = GetParam();
  const Body body = loadedBar(model);
  SceneSettings scene;
  scene.integrator = integrator;
  MAKE_GPU_OR_SKIP(gpu, body, scene);
  MassSpringSimulation cpu(body, scene);
  ASSERT_EQ(gpu->stepSize(), cpu.stepSize());
  const auto compare = [&](double t) {
    gpu->advance(t);
    cpu.advance(t);
    ASSERT_EQ(gpu->stepCount(), cpu.stepCount());
    const double dx = test::maxDistance(gpu->positions(), cpu.positions());
    const bool bitwise = test::bitwiseEqual(gpu->positions(), cpu.positions()) &&
      test::bitwiseEqual(gpu->velocities(), cpu.velocities());
    std::cout << materialModelName(model) << ", " << integratorName(integrator) << " t = " << t << " s, "
              << cpu.stepCount() << " steps: max |dx| / length = " << dx / kLength
              << (bitwise ? " (bitwise equal)" : "") << "\n";
    if (test::softwareRenderer(*gpu))
    {
      EXPECT_TRUE(bitwise);
    }
    EXPECT_LE(dx / kLength, test::kGpuRelativeTolerance) << gpu->glRenderer();
  };
  compare(0.0125); // the drive's quarter period: it is at its largest
  compare(0.03);

  // The supports' reactions from the GPU's state are the CPU's, and they are not nothing.
  const ConditionReadout onGpu = gpu->conditionReadout(), onCpu = cpu.conditionReadout();
  ASSERT_EQ(onGpu.reactions.size(), body.mesh.points.size());
  const double largest = largestReaction(onCpu);
  EXPECT_GT(largest, 1e-3);
  double difference = 0.0;
  for (std::size_t i = 0; i < onCpu.reactions.size(); ++i)
  {
    difference = std::max(difference, (onGpu.reactions[i] - onCpu.reactions[i]).norm());
  }
  EXPECT_LE(difference, 1e-9 * largest);
  ASSERT_EQ(onGpu.totals.size(), onCpu.totals.size());

  // Loads changed while the run plays (a widget moved): both take the new values from now on.
  std::vector<Condition> moved = body.conditions;
  moved[3].force = Vec3(1.0, -4.0, 0.5);
  moved[2].translation = Vec3(0.0, 0.003, 0.0);
  ASSERT_TRUE(gpu->setConditionValues(moved));
  ASSERT_TRUE(cpu.setConditionValues(moved));
  compare(0.045);

  // What is compared is the conditions' doing: the bar without them ends elsewhere.
  Body free = body;
  free.conditions.clear();
  MassSpringSimulation unheld(free, scene);
  unheld.advance(0.045);
  EXPECT_GT(test::maxDistance(unheld.positions(), cpu.positions()), 1e-3);
}

INSTANTIATE_TEST_SUITE_P(ModelsAndIntegrators, GpuConditions,
  ::testing::Combine(::testing::Values(MaterialModel::SpringNetwork, MaterialModel::StableNeoHookean),
    ::testing::Values(Integrator::Euler, Integrator::Midpoint, Integrator::Verlet, Integrator::EulerCromer)),
  test::modelAndIntegratorName);

TEST(GpuConditions, PressureAndPullAreLeftToTheCpuNamingTheCondition)
{
  for (ConditionKind kind : { ConditionKind::Pressure, ConditionKind::Pull })
  {
    Body body = loadedBar(MaterialModel::SpringNetwork);
    Condition follower;
    follower.name = "follower";
    follower.kind = kind;
    follower.points = pointsWhere(body.mesh, kLength);
    follower.pressure = 1000.0;
    follower.pullStiffness = 10.0;
    body.conditions.push_back(follower);
    std::string whyNot;
    const auto gpu = gpu::tryCreateGpuMassSpring(body, SceneSettings{}, whyNot);
    EXPECT_EQ(gpu, nullptr);
    EXPECT_NE(whyNot.find(conditionKindName(kind)), std::string::npos) << whyNot;
    EXPECT_NE(whyNot.find("\"follower\""), std::string::npos) << whyNot;
  }
}
