// Stable time step estimates: the amplification analysis and the simulation that obeys it.
#include "softbody/common/errors.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"
#include "softbody/massspring/stability.h"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

using namespace softbody;

TEST(Stability, AmplificationMatchesTheTextbookLimits)
{
  const double omega = 10.0;
  // Euler-Cromer / leapfrog: |lambda| = 1 up to h = 2 / omega, unstable beyond.
  EXPECT_NEAR(amplificationRadius(Integrator::EulerCromer, 0.19, omega, 0.0), 1.0, 1e-12);
  EXPECT_GT(amplificationRadius(Integrator::EulerCromer, 0.21, omega, 0.0), 1.0);
  EXPECT_NEAR(stableTimeStep(Integrator::Verlet, omega, 0.0, 0.0), 2.0 / omega, 1e-9);
  // Explicit Euler: |1 + i omega h| > 1 for every h: no stable step without damping.
  EXPECT_GT(amplificationRadius(Integrator::Euler, 1e-4, omega, 0.0), 1.0);
  EXPECT_EQ(stableTimeStep(Integrator::Euler, omega, 0.0, 0.0), 0.0);
  // With stiffness-proportional damping beta, under-damped modes need h <= beta.
  const double beta = 0.01; // zeta(omega) = 0.05
  EXPECT_NEAR(stableTimeStep(Integrator::Euler, omega, beta, beta), beta, 1e-6);
  // Damping shrinks the symplectic limit (2/w)(sqrt(1 + zeta^2) - zeta).
  const double zeta = beta * omega / 2;
  EXPECT_NEAR(stableTimeStep(Integrator::EulerCromer, omega, beta, beta),
    2.0 / omega * (std::sqrt(1 + zeta * zeta) - zeta), 1e-6);
}

TEST(Stability, FrequencyBoundIsAnUpperBoundOfASingleSpring)
{
  // One tet with three corners pinned: the free corner oscillates; its highest frequency is
  // below the Gershgorin bound, and the bound is within a small factor of it.
  TetMesh mesh;
  mesh.points = { Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1) };
  mesh.tets = { { 0, 1, 2, 3 } };
  BodyDescription body;
  body.mesh = mesh;
  body.pinned = { 1, 1, 1, 0 };
  body.material.mode = MaterialMode::Raw;
  body.material.raw = { 10.0, 0.0, 0.0, 0.0, 4.0 };
  MassSpringSimulation sim(body, SceneSettings{});
  // Free corner (0,0,1), mass 1, three springs to the pinned corners: stiffness matrix
  // K = sum k_e n n^T with k_e = k_D / l0^2; its largest eigenvalue bounds omega^2 from below.
  const auto& c = sim.elementConstants();
  Eigen::Matrix3d k = Eigen::Matrix3d::Zero();
  for (std::size_t e = 0; e < sim.topology().edges.size(); ++e)
  {
    const Edge& edge = sim.topology().edges[e];
    if (edge.b == 3)
    {
      const Vec3 n = (mesh.points[3] - mesh.points[edge.a]).normalized();
      k += c.springStiffness[e] * n * n.transpose();
    }
  }
  const double omegaTrue = std::sqrt(k.eigenvalues().real().maxCoeff() * sim.inverseMasses()[3]);
  EXPECT_GE(sim.highestFrequency(), omegaTrue);
  EXPECT_LE(sim.highestFrequency(), 3.0 * omegaTrue);
}

TEST(Stability, AutomaticStepRunsAndAFarLargerStepIsCaughtWithItsTime)
{
  BodyDescription body;
  body.mesh = makeTetBox(4, 4, 4, 0.05, Vec3(0, 0, 0.1));
  body.material.physical.dampingTime = 0.0;
  SceneSettings scene;
  scene.integrator = Integrator::Verlet;
  scene.floorEnabled = true;
  MassSpringSimulation automatic(body, scene);
  EXPECT_NO_THROW(automatic.advance(0.5));
  EXPECT_GT(automatic.stepSize(), 0.0);

  scene.timeStep = 4.0 * automatic.estimatedStableStep();
  MassSpringSimulation tooLarge(body, scene);
  ASSERT_FALSE(tooLarge.warnings().empty()); // the step above the estimate is reported
  try
  {
    tooLarge.advance(0.5);
    FAIL() << "a step 4x above the stability limit should blow up";
  }
  catch (const SimulationDivergedError& error)
  {
    EXPECT_GT(error.time, 0.0);
    EXPECT_LE(error.time, 0.5);
    EXPECT_NE(std::string(error.what()).find("t = "), std::string::npos);
  }
}
