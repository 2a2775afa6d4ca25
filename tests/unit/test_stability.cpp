// Stable time step estimates: the amplification analysis and the simulation that obeys it.
#include "softbody/common/errors.h"
#include "softbody/massspring/mass_spring_forces.h"
#include "softbody/massspring/mass_spring_setup.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"
#include "softbody/material/tet_elastic_forces.h"
#include "softbody/stability/element_frequency.h"
#include "softbody/stability/stability.h"

#include <Eigen/Eigenvalues>
#include <array>
#include <cstdio>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "test_support.h"

#include <cstdio>

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

namespace
{
/// One tet of raw springs (stiffness 10, density 4) at `points`, with the corners `pinned`.
Body springTet(const std::array<Vec3, 4>& points, std::vector<char> pinned = {})
{
  Body body;
  body.mesh.points.assign(points.begin(), points.end());
  body.mesh.tets = { { 0, 1, 2, 3 } };
  body.pinned = std::move(pinned);
  body.material.mode = MaterialMode::Raw;
  body.material.raw = { 10.0, 0.0, 0.0, 0.0, 4.0 };
  return body;
}
} // namespace

TEST(Stability, FrequencyEstimateOfASingleFreeCornerIsItsExactFrequency)
{
  // One tet with three corners pinned: the free corner oscillates in a 3-dimensional space, so
  // three Lanczos steps span it and the Lanczos estimate is its exact top frequency (the set-up
  // adds its deformation margin); the Gershgorin bound is above it.
  const Body body = springTet({ Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1) }, { 1, 1, 1, 0 });
  const TetMesh& mesh = body.mesh;
  MassSpringSimulation sim(body, SceneSettings{});
  // Free corner (0,0,1), mass 1, three springs to the pinned corners: stiffness matrix
  // K = sum k_e n n^T with k_e = k_D / l0^2; omega^2 is its largest eigenvalue over the mass.
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
  const LanczosFrequency lanczos =
    lanczosFrequencyEstimate(sim.topology(), c, sim.inverseMasses(), sim.restPositions(), kFrequencyLanczosSteps);
  EXPECT_EQ(lanczos.iterations, 3); // then the space is exhausted
  EXPECT_NEAR(lanczos.upperOmega, omegaTrue, 1e-9 * omegaTrue);
  const double gershgorin = gershgorinFrequencyBound(sim.topology(), c, sim.inverseMasses(), sim.restPositions());
  EXPECT_GE(gershgorin, omegaTrue);
  EXPECT_DOUBLE_EQ(sim.highestFrequency(), std::min(gershgorin, kDeformationMargin * lanczos.upperOmega));
}

TEST(Stability, GershgorinBoundHoldsWhereFreePointsPullOnEachOther)
{
  // A free tet of springs alone: each row of K has its diagonal block and the off-diagonal
  // blocks of its free neighbours, k n n^T each, so the row bound needs 2 k per spring (a
  // single free spring between two unit masses has omega^2 = 2 k exactly). Lanczos spans the
  // 12-dimensional space and gives the exact top frequency; the bound is above it.
  MassSpringSimulation sim(springTet({ Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 0.9, 0), Vec3(0.5, 0.3, 0.8) }), SceneSettings{});
  const auto& c = sim.elementConstants();
  const LanczosFrequency lanczos = lanczosFrequencyEstimate(sim.topology(), c, sim.inverseMasses(), sim.restPositions(), 12);
  const double gershgorin = gershgorinFrequencyBound(sim.topology(), c, sim.inverseMasses(), sim.restPositions());
  std::printf("free tet: Gershgorin %.6g rad/s, exact (Lanczos, %d steps) %.6g rad/s, %.3f of it\n", gershgorin,
    lanczos.iterations, lanczos.upperOmega, gershgorin / lanczos.upperOmega);
  EXPECT_GE(gershgorin, lanczos.upperOmega * (1.0 - 1e-12));
}

namespace
{
/// The exact omega_max of a body at rest from a dense eigensolve of M^-1/2 K M^-1/2, with K
/// assembled by central differences of a force kernel forces(x, f) at zero velocity (an
/// independent path: the estimate's matrix-free product is derived by hand).
template <class Forces>
double denseTopFrequency(const MassSpringSimulation& sim, const Forces& forces)
{
  const std::vector<Vec3>& rest = sim.restPositions();
  const std::vector<double>& w = sim.inverseMasses();
  const std::size_t n = rest.size();
  std::vector<Vec3> plus, minus;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  const double epsilon = 1e-7 * 0.05;
  for (std::size_t j = 0; j < 3 * n; ++j)
  {
    std::vector<Vec3> x = rest;
    x[j / 3][j % 3] += epsilon;
    forces(x, plus);
    x[j / 3][j % 3] -= 2 * epsilon;
    forces(x, minus);
    for (std::size_t i = 0; i < 3 * n; ++i)
    {
      // K = -df/dx, scaled by sqrt(w_i w_j) (pinned points drop out).
      a(i, j) = -(plus[i / 3][i % 3] - minus[i / 3][i % 3]) / (2 * epsilon) * std::sqrt(w[i / 3] * w[j / 3]);
    }
  }
  const Eigen::MatrixXd symmetric = 0.5 * (a + a.transpose());
  return std::sqrt(
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(symmetric, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff());
}

/// The spring network's, from the simulation's own force kernel.
double denseHighestFrequency(const MassSpringSimulation& sim)
{
  const std::vector<Vec3> zero(sim.restPositions().size(), Vec3::Zero());
  ForceScratch scratch;
  return denseTopFrequency(sim, [&](const std::vector<Vec3>& x, std::vector<Vec3>& f) {
    computeInternalForces(sim.topology(), sim.elementConstants(), x, zero, scratch, f);
  });
}

/// A continuum body's, from the law's own elastic forces, so the estimate's linear-elasticity
/// product is checked against the material it stands for.
double denseContinuumFrequency(const MassSpringSimulation& sim)
{
  const std::vector<Vec3> still(sim.restPositions().size(), Vec3::Zero());
  TetElasticScratch scratch;
  return denseTopFrequency(sim, [&](const std::vector<Vec3>& x, std::vector<Vec3>& f) {
    computeTetElasticForces(sim.topology(), sim.tetElasticConstants(), x, still, scratch, f);
  });
}
} // namespace

TEST(Stability, FrequencyEstimateIsJustAboveTheExactTopFrequency)
{
  // A regular box (dense top of the spectrum: the hard case for a few Lanczos steps) and a
  // jittered one with its bottom pinned and a sliver-like spread of element sizes: the set-up's
  // estimate must not be below the exact omega_max (else the automatic step can blow up) and
  // should be close above it (the Gershgorin bound is 1.4-2x high on the lab's meshes); the
  // plain top Ritz value is a lower bound.
  struct Case
  {
    const char* name;
    TetMesh mesh;
    bool pinBottom;
  };
  TetMesh jittered = makeTetBox(4, 3, 3, 0.02);
  jittered.points = test::jitter(jittered.points, 0.006);
  const Case cases[] = { { "regular 4x4x4 box", makeTetBox(4, 4, 4, 0.02), false },
    { "jittered box, bottom pinned", jittered, true } };
  for (const Case& c : cases)
  {
    Body body;
    body.mesh = c.mesh;
    body.pinned.assign(c.mesh.points.size(), 0);
    for (std::size_t i = 0; i < c.mesh.points.size() && c.pinBottom; ++i)
    {
      body.pinned[i] = c.mesh.points[i].z() < 1e-9 ? 1 : 0;
    }
    const MassSpringSimulation sim(body, SceneSettings{});
    const double exact = denseHighestFrequency(sim);
    const auto& k = sim.elementConstants();
    const auto& w = sim.inverseMasses();
    const LanczosFrequency lanczos =
      lanczosFrequencyEstimate(sim.topology(), k, w, sim.restPositions(), kFrequencyLanczosSteps);
    const double gershgorin = gershgorinFrequencyBound(sim.topology(), k, w, sim.restPositions());
    std::printf("%s: omega_max %.6g rad/s; Lanczos %.6g (Ritz %.6g), Gershgorin %.6g\n", c.name, exact,
      lanczos.upperOmega, lanczos.ritzOmega, gershgorin);
    // 1e-6: the finite-difference Hessian's own error.
    EXPECT_GE(lanczos.upperOmega, exact * (1 - 1e-6)) << c.name;
    EXPECT_LE(lanczos.upperOmega, 1.05 * exact) << c.name;
    EXPECT_LE(lanczos.ritzOmega, exact * (1 + 1e-6)) << c.name;
    EXPECT_GE(gershgorin, exact * (1 - 1e-6)) << c.name;
    EXPECT_EQ(sim.highestFrequency(), std::min(gershgorin, kDeformationMargin * lanczos.upperOmega)) << c.name;
  }
}


TEST(Stability, ContinuumFrequencyEstimateIsJustAboveTheExactTopFrequencyOfEitherLaw)
{
  // The continuum models' estimate runs Lanczos on linear elasticity with the typed E and nu,
  // which both laws must linearize to at rest: on a jittered box with its bottom pinned (and a
  // spread of element sizes) and at nu = 0.3 and 0.45, it is not below the exact omega_max of
  // either law's own forces, and within 5 % above it; the Gershgorin bound it replaces is above
  // both.
  TetMesh jittered = makeTetBox(4, 3, 3, 0.02);
  jittered.points = test::jitter(jittered.points, 0.006);
  for (MaterialModel model : { MaterialModel::Corotated, MaterialModel::StableNeoHookean })
  {
    for (double nu : { 0.3, 0.45 })
    {
      Body body;
      body.mesh = jittered;
      body.material.model = model;
      body.material.physical.youngsModulus = 1e6;
      body.material.physical.poissonRatio = nu;
      body.pinned.assign(jittered.points.size(), 0);
      for (std::size_t i = 0; i < jittered.points.size(); ++i)
      {
        body.pinned[i] = jittered.points[i].z() < 1e-9 ? 1 : 0;
      }
      const MassSpringSimulation sim(body, SceneSettings{});
      const double exact = denseContinuumFrequency(sim);
      const auto& w = sim.inverseMasses();
      const LanczosFrequency lanczos = continuumLanczosEstimate(
        sim.topology(), sim.tetElasticConstants(), w, sim.restPositions(), kFrequencyLanczosSteps);
      const double gershgorin = continuumGershgorinBound(sim.topology(), sim.tetElasticConstants(), w, sim.restPositions());
      std::printf("%s, nu %.2f: omega_max %.6g rad/s; Lanczos %.6g (Ritz %.6g), Gershgorin %.6g (%.2f x)\n",
        materialModelName(model), nu, exact, lanczos.upperOmega, lanczos.ritzOmega, gershgorin, gershgorin / exact);
      EXPECT_GE(lanczos.upperOmega, exact * (1 - 1e-6)) << materialModelName(model) << " nu " << nu;
      EXPECT_LE(lanczos.upperOmega, 1.05 * exact) << materialModelName(model) << " nu " << nu;
      EXPECT_LE(lanczos.ritzOmega, exact * (1 + 1e-6)) << materialModelName(model) << " nu " << nu;
      EXPECT_GE(gershgorin, exact * (1 - 1e-6)) << materialModelName(model) << " nu " << nu;
      EXPECT_EQ(sim.highestFrequency(), std::min(gershgorin, kDeformationMargin * lanczos.upperOmega));
      // The same body 1,000 km from the origin (its start vector, hashed from the positions,
      // differs): the estimate still brackets the same omega_max.
      Body far = body;
      for (Vec3& p : far.mesh.points)
      {
        p += Vec3(1e6, -2e6, 5e5);
      }
      const MassSpringSimulation farSim(far, SceneSettings{});
      const LanczosFrequency farLanczos = continuumLanczosEstimate(farSim.topology(), farSim.tetElasticConstants(),
        farSim.inverseMasses(), farSim.restPositions(), kFrequencyLanczosSteps);
      EXPECT_GE(farLanczos.upperOmega, exact * (1 - 1e-6)) << materialModelName(model) << " nu " << nu << ", far";
      EXPECT_LE(farLanczos.upperOmega, 1.05 * exact) << materialModelName(model) << " nu " << nu << ", far";
    }
  }
}

TEST(Stability, ContinuumFrequencyEstimateIsTheSameAtAnyThreadCount)
{
  Body body;
  body.mesh = makeTetBox(12, 10, 8, 0.01);
  body.material.model = MaterialModel::Corotated;
  auto estimate = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    const MassSpringSimulation sim(body, SceneSettings{});
    return continuumLanczosEstimate(sim.topology(), sim.tetElasticConstants(), sim.inverseMasses(),
      sim.restPositions(), kFrequencyLanczosSteps);
  };
  const LanczosFrequency one = estimate(1), two = estimate(2);
  EXPECT_EQ(one.upperOmega, two.upperOmega);
  EXPECT_EQ(one.ritzOmega, two.ritzOmega);
  EXPECT_EQ(one.iterations, kFrequencyLanczosSteps);
}

TEST(Stability, FrequencyEstimateIsTheSameAtAnyThreadCount)
{
  Body body;
  body.mesh = makeTetBox(12, 10, 8, 0.01); // ~5k tets: several parallel chunks per pass
  auto estimate = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    const MassSpringSimulation sim(body, SceneSettings{});
    return lanczosFrequencyEstimate(sim.topology(), sim.elementConstants(), sim.inverseMasses(),
      sim.restPositions(), kFrequencyLanczosSteps);
  };
  const LanczosFrequency one = estimate(1), two = estimate(2);
  EXPECT_EQ(one.upperOmega, two.upperOmega);
  EXPECT_EQ(one.ritzOmega, two.ritzOmega);
  EXPECT_EQ(one.iterations, kFrequencyLanczosSteps);
}

namespace
{
/// Whether `steps` steps of h, from the rest shape with small random velocities (no gravity, no
/// floor), multiply the body's energy by more than 1000 (or blow it up).
bool blowsUp(const Body& body, SceneSettings scene, double h, int steps)
{
  scene.timeStep = h;
  scene.gravity = Vec3::Zero();
  scene.floorEnabled = false;
  scene.strainLimit = 0.0;
  MassSpringSimulation sim(body, scene);
  DynamicState start = sim.state();
  start.velocities = test::randomVectors(start.positions.size(), 1e-3);
  sim.restoreState(start);
  auto energy = [&] { return sim.mechanicalEnergy(); };
  const double e0 = energy();
  try
  {
    sim.advance(steps * h);
  }
  catch (const SimulationDivergedError&)
  {
    return true;
  }
  return !(energy() < 1e3 * e0);
}

/// The largest stable step of the simulation itself, bisected between lo (stable) and hi.
double bisectedLimit(const Body& body, const SceneSettings& scene, double lo, double hi)
{
  for (int iteration = 0; iteration < 12; ++iteration)
  {
    const double mid = 0.5 * (lo + hi);
    (blowsUp(body, scene, mid, 3000) ? hi : lo) = mid;
  }
  return lo;
}
} // namespace

TEST(Stability, AutomaticStepIsSafeAndWithinTwoOfTheBisectedLimit)
{
  // The automatic step (0.9 x the estimate from 1.2 x the Lanczos omega_max) against the largest step
  // at which the body itself stays stable, found by bisection (3000 steps from random
  // velocities, energy x1000 = unstable; resolution ~0.1%). Below it always (else the automatic
  // step blows up), and not wasteful: at least half of it (the Gershgorin bound alone
  // gives 0.14 to 0.43 of it here). Undamped Verlet and the damped methods (whose
  // over-damped top modes square any excess in omega_max) alike.
  struct Case
  {
    Integrator integrator;
    double dampingTime;
  };
  const Case cases[] = {
    { Integrator::Verlet, 0.0 },
    { Integrator::EulerCromer, 2e-3 },
    { Integrator::Midpoint, 2e-3 },
    { Integrator::Euler, 2e-3 },
  };
  for (const Case& c : cases)
  {
    Body body;
    body.mesh = makeTetBox(2, 2, 2, 0.05, Vec3(0, 0, 0.1));
    body.material.physical.dampingTime = c.dampingTime;
    SceneSettings scene;
    scene.integrator = c.integrator;
    const MassSpringSimulation automatic(body, scene);
    const double h = automatic.stepSize();
    ASSERT_GT(h, 0.0);
    const double limit = bisectedLimit(body, scene, 0.5 * h, 8.0 * h);
    const double ratio = h / limit;
    std::printf("%s: automatic step %.4g s, bisected limit %.4g s, ratio %.3f\n",
      integratorName(c.integrator), h, limit, ratio);
    EXPECT_LT(ratio, 1.0) << integratorName(c.integrator);
    EXPECT_GE(ratio, 0.5) << integratorName(c.integrator);
    EXPECT_FALSE(blowsUp(body, scene, h, 3000)) << integratorName(c.integrator);
  }
}

TEST(Stability, ContinuumAutomaticStepIsSafeAndWithinTwoOfTheBisectedLimit)
{
  // The same for the finite-element models, whose estimate is the Lanczos one on linear
  // elasticity: below the bisected limit, and at least half of it (the Gershgorin bound they
  // used alone gives 2.3-2.9x omega_max on a jittered box, Stability.ContinuumFrequencyEstimate*).
  for (MaterialModel model : { MaterialModel::Corotated, MaterialModel::StableNeoHookean })
  {
    for (const auto& [integrator, dampingTime] :
      { std::pair{ Integrator::Verlet, 0.0 }, std::pair{ Integrator::EulerCromer, 2e-3 } })
    {
      Body body;
      body.mesh = makeTetBox(2, 2, 2, 0.05, Vec3(0, 0, 0.1));
      body.material.model = model;
      body.material.physical.dampingTime = dampingTime;
      SceneSettings scene;
      scene.integrator = integrator;
      const MassSpringSimulation automatic(body, scene);
      const double h = automatic.stepSize();
      ASSERT_GT(h, 0.0);
      const double limit = bisectedLimit(body, scene, 0.5 * h, 8.0 * h);
      const double ratio = h / limit;
      std::printf("%s, %s: automatic step %.4g s, bisected limit %.4g s, ratio %.3f\n", materialModelName(model),
        integratorName(integrator), h, limit, ratio);
      EXPECT_LT(ratio, 1.0) << materialModelName(model) << ", " << integratorName(integrator);
      EXPECT_GE(ratio, 0.5) << materialModelName(model) << ", " << integratorName(integrator);
      EXPECT_FALSE(blowsUp(body, scene, h, 3000)) << materialModelName(model) << ", " << integratorName(integrator);
    }
  }
}

TEST(Stability, AFarLargerStepIsCaughtWithItsTime)
{
  Body body;
  body.mesh = makeTetBox(4, 4, 4, 0.05, Vec3(0, 0, 0.1));
  body.material.physical.dampingTime = 0.0;
  SceneSettings scene;
  scene.integrator = Integrator::Verlet;
  scene.floorEnabled = true;
  MassSpringSimulation automatic(body, scene);
  automatic.advance(0.5);
  EXPECT_GT(automatic.stepCount(), 100u);

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

namespace
{
Body steelBar(double dampingTime)
{
  Body body;
  body.mesh = makeTetBox(2, 2, 8, 0.0125, Vec3(0, 0, 0.1)); // a 2.5 x 2.5 x 10 cm bar
  body.material.physical.youngsModulus = 2.0e11;
  body.material.physical.poissonRatio = 0.3;
  body.material.physical.density = 7850.0;
  body.material.physical.dampingTime = dampingTime;
  return body;
}
} // namespace

TEST(Stability, SteelHasAStableStepAndRunsAtIt)
{
  // Stiff and damped: the step is tiny (overdamped stiff modes need h < 2 / (beta w^2)) but it
  // exists, and the bar falls at it without blowing up. (An estimate of 0 here would make the
  // set-up take 1 ms steps, and the run would blow up.)
  MassSpringSimulation damped(steelBar(2.0e-3), SceneSettings{});
  EXPECT_GT(damped.estimatedStableStep(), 0.0);
  EXPECT_LE(damped.stepSize(), damped.estimatedStableStep());
  const double h = damped.stepSize();
  damped.advance(200 * h);
  for (const Vec3& v : damped.velocities())
  {
    EXPECT_TRUE(v.allFinite());
    EXPECT_LT(v.norm(), 1.0); // 200 tiny steps of free fall: still almost at rest
  }

  // Without damping the step is the symplectic limit ~2 / w_max, far larger, and a 2 ms fall
  // stays a rigid fall (no spurious vibration grows).
  MassSpringSimulation undamped(steelBar(0.0), SceneSettings{});
  EXPECT_GT(undamped.stepSize(), 100.0 * h);
  undamped.advance(2.0e-3);
  for (std::size_t i = 0; i < undamped.positions().size(); ++i)
  {
    const Vec3 fall = undamped.positions()[i] - undamped.restPositions()[i];
    EXPECT_NEAR(fall.z(), -0.5 * 9.81 * 2.0e-3 * 2.0e-3, 1e-6);
  }
}

TEST(Stability, ALongRunIsAnnouncedWithItsCauseAndRemedies)
{
  // The steel bar to 1 s: millions of steps, limited by damping; the warning says how many,
  // how long, why, and what to change.
  MassSpringSimulation steel(steelBar(2.0e-3), SceneSettings{});
  const std::string warning = steel.longRunWarning(1.0);
  EXPECT_NE(warning.find("steps of"), std::string::npos) << warning;
  EXPECT_NE(warning.find("limited by damping"), std::string::npos) << warning;
  EXPECT_NE(warning.find("with DampingTime 0 the stable step would be"), std::string::npos) << warning;
  EXPECT_NE(warning.find("MaxInverseMass"), std::string::npos) << warning;
  // A soft body for a few seconds needs no warning.
  Body jelly;
  jelly.mesh = makeTetBox(3, 3, 3, 0.05, Vec3(0, 0, 0.2));
  MassSpringSimulation soft(jelly, SceneSettings{});
  EXPECT_EQ(soft.longRunWarning(3.0), "") << soft.estimatedStableStep();
}

TEST(Stability, LongRunEstimateCountsStepsAndTetSteps)
{
  // 1 s at 1 us steps on 30,000 tets: 1e6 steps x 3e4 tets / 3e7 tet-steps per second = 1000 s.
  StepCost cost;
  cost.step = 1.0e-6;
  cost.stableStep = 1.0e-6;
  cost.undampedStableStep = 1.0e-6; // not damping-limited: no damping advice
  cost.tetCount = 30000;
  const std::string warning = longRunWarning(cost, 1.0);
  EXPECT_NE(warning.find("takes 1e+06 steps of 1e-06 s: about 16.7 minutes"), std::string::npos) << warning;
  EXPECT_EQ(warning.find("DampingTime"), std::string::npos) << warning;
  cost.integrator = Integrator::Midpoint; // two force evaluations per step
  EXPECT_NE(longRunWarning(cost, 1.0).find("about 33.3 minutes"), std::string::npos);
  cost.tetCount = 10; // more than a million cheap steps still deserve a word; fewer do not
  EXPECT_FALSE(longRunWarning(cost, 2.0).empty());
  EXPECT_TRUE(longRunWarning(cost, 0.5).empty());

  // The stepper's estimate is the set-up's (the tet count survives the set-up's hand-over).
  const MassSpringSimulation steel(steelBar(2.0e-3), SceneSettings{});
  EXPECT_EQ(steel.longRunWarning(1.0),
    longRunWarning(stepCostOf(prepareMassSpring(steelBar(2.0e-3), SceneSettings{})), 1.0));
}
