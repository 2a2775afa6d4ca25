// The GPU's floor contacts against the analytic answers the CPU's contact tests use: Coulomb
// friction on an incline (sliding at g (sin theta - mu cos theta), sticking while
// mu >= tan theta) and restitution (a rebound of e^2 times the drop), each also against the CPU
// stepper on the same scene (bitwise on Mesa llvmpipe). Skipped where no EGL / OpenGL 4.3
// context exists.
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"
#include "gpu_test_support.h"
#include "incline_scene.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

using namespace softbody;
using test::slideBetween;
using test::tilt;

namespace
{
constexpr double kPi = 3.14159265358979323846;
constexpr double kG = 9.81;
constexpr double kMargin = 0.001;

/// A 12 cm box resting on the floor tilted by `angle`, friction mu (static = dynamic).
struct Incline
{
  Body body;
  SceneSettings scene;
};

Incline incline(double angle, double mu)
{
  Incline s;
  s.body.mesh = makeTetBox(3, 3, 3, 0.04, Vec3(-0.06, -0.06, kMargin));
  for (Vec3& p : s.body.mesh.points)
  {
    p = tilt(p, angle);
  }
  s.scene.integrator = Integrator::EulerCromer;
  s.scene.floorEnabled = true;
  s.scene.floor.normal = tilt(Vec3::UnitZ(), angle);
  s.scene.collisions.margin = kMargin;
  s.scene.collisions.staticFriction = mu;
  s.scene.collisions.dynamicFriction = mu;
  return s;
}

} // namespace

TEST(GpuFloorContacts, OnAnInclineABodySlidesAtGTimesSinMinusMuCos)
{
  const double angle = 30.0 * kPi / 180.0; // tan = 0.577
  for (double mu : { 0.0, 0.3 })
  {
    const Incline s = incline(angle, mu);
    MAKE_GPU_OR_SKIP(gpu, s.body, s.scene);
    MassSpringSimulation cpu(s.body, s.scene);
    const test::Slide onGpu = slideBetween(*gpu, angle, 0.1, 0.3);
    const test::Slide onCpu = slideBetween(cpu, angle, 0.1, 0.3);
    const double expected = kG * (std::sin(angle) - mu * std::cos(angle));
    std::printf("  mu %.1f: GPU slides at %.4f m/s^2, CPU at %.4f, g (sin - mu cos) = %.4f\n", mu,
      onGpu.acceleration, onCpu.acceleration, expected);
    EXPECT_NEAR(onGpu.acceleration, expected, 0.03 * kG) << "mu = " << mu;
    EXPECT_LE(test::maxDistance(gpu->positions(), cpu.positions()) / 0.12,
      test::afterThresholdStages(*gpu).position);
  }
}

TEST(GpuFloorContacts, OnAnInclineABodySticksWhenMuIsAboveTanTheta)
{
  // mu = 0.6 > tan 30 deg = 0.577. Measured from 1 s, once the sag set on placing it has
  // settled: until then it slips while its sag vibrates (each point's grip follows its own
  // normal load, which the vibration modulates), 3.3 cm in the first second.
  const double angle = 30.0 * kPi / 180.0;
  const Incline s = incline(angle, 0.6);
  MAKE_GPU_OR_SKIP(gpu, s.body, s.scene);
  MassSpringSimulation cpu(s.body, s.scene);
  const test::Slide onGpu = slideBetween(*gpu, angle, 1.0, 1.5);
  const test::Slide onCpu = slideBetween(cpu, angle, 1.0, 1.5);
  std::printf("  mu 0.6: GPU travel %.2e m, CPU %.2e m from 1 s to 1.5 s\n", onGpu.travel, onCpu.travel);
  EXPECT_LT(std::abs(onGpu.travel), 1.0e-4);
  EXPECT_LE(test::maxDistance(gpu->positions(), cpu.positions()) / 0.12,
    test::afterThresholdStages(*gpu).position);
}

TEST(GpuFloorContacts, RestitutionGivesAReboundOfESquaredTimesTheDropHeight)
{
  // A body of zero stiffness, whose points fall and bounce as free particles, each from its
  // own height: a point that arrives at v leaves at e v and climbs back e^2 h.
  for (double e : { 0.5, 1.0 })
  {
    Body body;
    body.mesh = makeTetBox(2, 2, 2, 0.05, Vec3(-0.05, -0.05, 0.2));
    body.material.mode = MaterialMode::Raw;
    body.material.raw.distanceStiffness = 0.0;
    body.material.raw.distanceDamping = 0.0;
    body.material.raw.volumeStiffness = 0.0;
    body.material.raw.volumeDamping = 0.0;
    SceneSettings scene;
    scene.integrator = Integrator::EulerCromer;
    scene.floorEnabled = true;
    scene.timeStep = 1.0e-4;
    scene.collisions.margin = kMargin;
    scene.collisions.restitution = e;
    MAKE_GPU_OR_SKIP(gpu, body, scene);
    MassSpringSimulation cpu(body, scene);
    const std::size_t n = gpu->positions().size();
    std::vector<double> drop(n), peak(n, 0.0);
    for (std::size_t i = 0; i < n; ++i)
    {
      drop[i] = gpu->positions()[i].z() - kMargin; // falls this far before it touches
    }
    for (int k = 1; k <= 600; ++k)
    {
      gpu->advance(k * 1.0e-3); // the highest point lands at 0.25 s and is back up by 0.5 s
      for (std::size_t i = 0; i < n; ++i)
      {
        if (gpu->velocities()[i].z() > 0.0 || peak[i] > 0.0)
        {
          peak[i] = std::max(peak[i], gpu->positions()[i].z() - kMargin);
        }
      }
    }
    double worst = 0.0;
    for (std::size_t i = 0; i < n; ++i)
    {
      worst = std::max(worst, std::abs(peak[i] - e * e * drop[i]) / drop[i]);
    }
    cpu.advance(0.6);
    std::printf("  restitution %.1f: GPU rebound / drop within %.4f of e^2 = %.2f for all %zu points\n",
      e, worst, e * e, n);
    EXPECT_LT(worst, 0.01) << "e = " << e;
    EXPECT_LE(test::maxDistance(gpu->positions(), cpu.positions()) / 0.3,
      test::afterThresholdStages(*gpu).position);
  }
}

TEST(GpuFloorContacts, FarFromTheOriginTheGpuSlidesAsTheCpuForEitherMaterial)
{
  // A mesh in scanner or site coordinates: the incline and its box moved 10 km away. The
  // contacts and the elements see differences of large coordinates, which round alike on both
  // devices only if every operation is the same.
  const double angle = 30.0 * kPi / 180.0;
  const Vec3 far(1.0e4, -1.0e4, 0.0);
  for (MaterialModel model : { MaterialModel::SpringNetwork, MaterialModel::StableNeoHookean })
  {
    Incline s = incline(angle, 0.3);
    for (Vec3& p : s.body.mesh.points)
    {
      p += far;
    }
    s.scene.floor.origin = far;
    s.body.material.model = model;
    MAKE_GPU_OR_SKIP(gpu, s.body, s.scene);
    MassSpringSimulation cpu(s.body, s.scene);
    const test::Slide onGpu = slideBetween(*gpu, angle, 0.1, 0.2);
    slideBetween(cpu, angle, 0.1, 0.2);
    const double expected = kG * (std::sin(angle) - 0.3 * std::cos(angle));
    std::printf("  %s 10 km away: GPU slides at %.4f m/s^2, g (sin - mu cos) = %.4f, GPU - CPU %.2e m\n",
      materialModelName(model), onGpu.acceleration, expected, test::maxDistance(gpu->positions(), cpu.positions()));
    EXPECT_NEAR(onGpu.acceleration, expected, 0.05 * kG) << materialModelName(model);
    EXPECT_LE(test::maxDistance(gpu->positions(), cpu.positions()) / 0.12,
      test::afterThresholdStages(*gpu).position);
  }
}
