// The PBD/XPBD step as a whole: free fall, momentum, pins, floor response, the solver
// comparisons of the PBD thesis, determinism across thread counts, breaking and plasticity.
#include "softbody/pbd/cloth.h"
#include "scenes/stretched_cloth.h"
#include "softbody/common/errors.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"
#include "softbody/pbd/pbd_simulation.h"
#include "pbd_test_bodies.h"

#include "test_support.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace softbody
{
namespace
{
Body boxBody(int n, double cell, const Vec3& origin = Vec3::Zero())
{
  return test::pbdBoxBody(n, cell, origin);
}

Vec3 centerOfMass(const PbdSimulation& sim, const std::vector<double>& mass)
{
  Vec3 c = Vec3::Zero();
  double total = 0.0;
  for (std::size_t i = 0; i < mass.size(); ++i)
  {
    c += mass[i] * sim.positions()[i];
    total += mass[i];
  }
  return c / total;
}

std::vector<double> massesOf(const PbdSimulation& sim)
{
  std::vector<double> m;
  for (double w : sim.inverseMasses())
  {
    m.push_back(w > 0 ? 1.0 / w : 0.0);
  }
  return m;
}

TEST(PbdSimulation, FreeFallFollowsSymplecticEulerAndVerletAgrees)
{
  PbdSettings settings;
  settings.iterations = 5;
  PbdSimulation euler(boxBody(2, 0.1), settings);
  settings.prediction = PbdPrediction::Verlet;
  PbdSimulation verlet(boxBody(2, 0.1), settings);
  const double h = 0.01;
  const int steps = 50;
  for (int s = 0; s < steps; ++s)
  {
    euler.step(h);
    verlet.step(h);
  }
  // Symplectic Euler: z_n = -g h^2 n (n + 1) / 2, i.e. g t^2 / 2 plus g t h / 2. The body is at
  // rest internally, so every particle falls the same.
  const double expected = -9.81 * h * h * steps * (steps + 1) / 2.0;
  for (std::size_t i = 0; i < euler.positions().size(); ++i)
  {
    EXPECT_NEAR(euler.positions()[i].z() - euler.restPositions()[i].z(), expected, 1e-12);
    EXPECT_NEAR((verlet.positions()[i] - euler.positions()[i]).norm(), 0.0, 1e-12);
  }
}

TEST(PbdSimulation, InternalConstraintsConserveLinearMomentum)
{
  // Every projection moves its particles by mass-weighted gradients that sum to zero. Averaged
  // Jacobi is the exception, by design: each particle divides its sum by its own constraint
  // count, which trades exact momentum for stability, so it is not in this list.
  for (PbdSolver solver : { PbdSolver::GaussSeidel, PbdSolver::ParallelGaussSeidel })
  {
    PbdSettings settings;
    settings.gravity.setZero();
    settings.solver = solver;
    settings.volumes.compliance = 1e-9;
    PbdSimulation sim(boxBody(3, 0.1), settings);
    DynamicState kicked = sim.state();
    kicked.positions = test::jitter(kicked.positions, 0.02);
    kicked.velocities = test::randomVectors(kicked.velocities.size(), 1.0);
    sim.restoreState(kicked);
    const std::vector<double> m = massesOf(sim);
    auto momentum = [&] {
      Vec3 p = Vec3::Zero();
      for (std::size_t i = 0; i < m.size(); ++i)
      {
        p += m[i] * sim.velocities()[i];
      }
      return p;
    };
    const Vec3 before = momentum();
    for (int s = 0; s < 20; ++s)
    {
      sim.step(0.005);
    }
    EXPECT_LT((momentum() - before).norm(), 1e-12 * (1.0 + before.norm())) << int(solver);
  }
}

TEST(PbdSimulation, PinnedParticlesNeverMove)
{
  ClothSpec spec;
  spec.particlesAlong1 = spec.particlesAlong2 = 10;
  spec.pins = ClothPins::Point2Corners; // a horizontal sheet held by two corners
  PbdSettings settings;
  PbdSimulation sim(makeCloth(spec), settings);
  sim.advance(1.0);
  EXPECT_EQ(sim.positions()[90], sim.restPositions()[90]);
  EXPECT_EQ(sim.positions()[99], sim.restPositions()[99]);
  EXPECT_LT(sim.positions()[0].z(), -0.1); // the rest hangs down
}

TEST(PbdSimulation, RestitutionAndFrictionAtTheFloor)
{
  // A flat cloth hits the floor at speed v: it leaves at e v. Then it slides with initial speed
  // u and Coulomb friction slows it by mu g per second.
  ClothSpec spec;
  spec.particlesAlong1 = spec.particlesAlong2 = 4;
  spec.origin = Vec3(0, 0, 0.5);
  spec.point1 = Vec3(1, 0, 0.5);
  spec.point2 = Vec3(0, 1, 0.5);
  PbdSettings settings;
  settings.floorEnabled = true;
  settings.collisions.restitution = 0.5;
  settings.timeStep = 1e-3;
  PbdSimulation bounce(makeCloth(spec), settings);
  double impact = 0.0, rebound = 0.0;
  for (int s = 0; s < 600 && rebound <= 0.0; ++s)
  {
    const double before = bounce.velocities()[0].z();
    bounce.step(1e-3);
    if (bounce.velocities()[0].z() > 0.0)
    {
      impact = before - 9.81e-3; // the speed it arrived with, gravity kick included
      rebound = bounce.velocities()[0].z();
    }
  }
  ASSERT_LT(impact, -2.0);
  EXPECT_NEAR(rebound, -0.5 * impact, 1e-9);

  spec.origin.z() = spec.point1.z() = spec.point2.z() = 0.0;
  settings.collisions.restitution = 0.0;
  settings.collisions.staticFriction = settings.collisions.dynamicFriction = 0.3;
  PbdSimulation slide(makeCloth(spec), settings);
  DynamicState moving = slide.state();
  std::fill(moving.velocities.begin(), moving.velocities.end(), Vec3(2.0, 0, 0));
  slide.restoreState(moving);
  slide.advance(0.4);
  // v(t) = u - mu g t while sliding (it stops at t = 0.68 s).
  EXPECT_NEAR(slide.velocities()[5].x(), 2.0 - 0.3 * 9.81 * 0.4, 0.01);
}

TEST(PbdSimulation, FrictionCarriesTheWeightOfTheWholeBody)
{
  // A block three particle layers thick slides on the floor with initial speed u: Coulomb
  // friction takes mu g per second off every particle's speed, the upper layers' weight
  // included (it reaches the floor through the constraints). Counting only each bottom
  // particle's own weight slowed it by a third of that.
  Body body;
  const TetMesh mesh = makeTetBox(2, 2, 2, 0.05);
  body.mesh.points = mesh.points;
  body.mesh.tets = mesh.tets;
  PbdSettings settings;
  settings.formulation = PbdFormulation::Pbd;
  settings.floorEnabled = true;
  settings.collisions.staticFriction = settings.collisions.dynamicFriction = 0.3;
  settings.timeStep = 1e-3;
  PbdSimulation slide(body, settings);
  DynamicState moving = slide.state();
  std::fill(moving.velocities.begin(), moving.velocities.end(), Vec3(2.0, 0, 0));
  slide.restoreState(moving);
  slide.advance(0.4);
  double vx = 0.0;
  for (const Vec3& v : slide.velocities())
  {
    vx += v.x() / double(slide.velocities().size());
  }
  EXPECT_NEAR(vx, 2.0 - 0.3 * 9.81 * 0.4, 0.05);
}

// Residual history of one step of the thesis's test: a 50 x 50 cloth stretched 16 times and
// released (no gravity), at PBD stiffness 1.
std::vector<double> stretchedClothResiduals(PbdSolver solver, double relaxation, int iterations)
{
  ClothSpec spec;
  spec.particlesAlong1 = spec.particlesAlong2 = 50;
  PbdSettings settings;
  settings.formulation = PbdFormulation::Pbd;
  settings.solver = solver;
  settings.relaxation = relaxation;
  settings.iterations = iterations;
  return scenes::stretchedClothAfterOneStep(spec, settings)->convergence().residualHistory;
}

TEST(PbdSimulation, GaussSeidelConvergesFasterPerIterationThanJacobi)
{
  const int n = 150;
  const std::vector<double> gs = stretchedClothResiduals(PbdSolver::GaussSeidel, 1.0, n);
  const std::vector<double> jacobi = stretchedClothResiduals(PbdSolver::Jacobi, 1.0, n);
  const std::vector<double> colored = stretchedClothResiduals(PbdSolver::ParallelGaussSeidel, 1.0, n);
  ASSERT_EQ(gs.size(), std::size_t(n));
  ASSERT_EQ(jacobi.size(), std::size_t(n));
  for (int k = 0; k < n; ++k)
  {
    EXPECT_LT(gs[k], jacobi[k]) << "iteration " << k;
  }
  // Colored Gauss-Seidel visits the constraints in color order, which spreads a correction
  // less far per sweep than row order: it starts behind (the 16x stretch is far from linear)
  // but converges at Gauss-Seidel's rate, so it overtakes Jacobi.
  const auto rate = [](const std::vector<double>& r) { return r.back() / r[49]; };
  EXPECT_LT(rate(colored), 0.8 * rate(jacobi));
  EXPECT_LT(rate(gs), 0.8 * rate(jacobi));
  EXPECT_LT(colored.back(), 0.85 * jacobi.back());
  EXPECT_LT(gs.back(), 0.65 * jacobi.back());
}

// The thesis's hanging 64 x 64 cloth: the mean strain of its structural links after 1 s at
// 60 Hz. PBD at stiffness 1 is as stiff as its iterations make it; XPBD's compliance sets a
// material stretch that more iterations only approach.
double hangingClothStretch(PbdFormulation formulation, int iterations)
{
  ClothSpec spec;
  spec.particlesAlong1 = spec.particlesAlong2 = 64;
  spec.origin = Vec3(0, 0, 0);
  spec.point1 = Vec3(1, 0, 0);
  spec.point2 = Vec3(0, 0, 1);
  spec.pins = ClothPins::Point2Corners;
  spec.totalMass = 1.0;
  PbdSettings settings;
  settings.formulation = formulation;
  settings.iterations = iterations;
  settings.links.stiffness = 1.0;
  settings.links.compliance = 0.05; // [m/N]
  settings.damping = 2.0;
  settings.timeStep = 1.0 / 60.0;
  PbdSimulation sim(makeCloth(spec), settings);
  sim.advance(1.0);
  // Mean strain of the structural links: those one grid spacing long (the solver stores its
  // links in its own order, so they are found by their rest length, not by index).
  double strain = 0.0;
  const DistanceBatch& links = sim.links();
  std::size_t structural = 0;
  for (std::size_t c = 0; c < links.size(); ++c)
  {
    if (std::abs(links.rest[c] - 1.0 / 63.0) > 1e-9)
    {
      continue;
    }
    const auto& e = links.ends[c];
    strain += (sim.positions()[e[0]] - sim.positions()[e[1]]).norm() / links.rest[c] - 1.0;
    ++structural;
  }
  EXPECT_EQ(structural, 2u * 64u * 63u);
  return strain / double(structural);
}

TEST(PbdSimulation, XpbdStretchDependsMuchLessOnIterationsThanPbd)
{
  const double pbd20 = hangingClothStretch(PbdFormulation::Pbd, 20);
  const double pbd160 = hangingClothStretch(PbdFormulation::Pbd, 160);
  const double xpbd20 = hangingClothStretch(PbdFormulation::Xpbd, 20);
  const double xpbd160 = hangingClothStretch(PbdFormulation::Xpbd, 160);
  std::printf("mean strain PBD 20: %.5f, 160: %.5f; XPBD 20: %.5f, 160: %.5f\n", pbd20, pbd160, xpbd20, xpbd160);
  const double pbdChange = std::abs(pbd20 - pbd160) / pbd160;
  const double xpbdChange = std::abs(xpbd20 - xpbd160) / xpbd160;
  EXPECT_LT(xpbdChange, 0.25 * pbdChange);
}

std::vector<Vec3> runWithThreads(PbdSolver solver, int threads)
{
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
  PbdSettings settings;
  settings.solver = solver;
  settings.floorEnabled = true;
  settings.volumes.compliance = 1e-8;
  PbdSimulation sim(boxBody(6, 0.05, Vec3(0, 0, 0.1)), settings);
  DynamicState start = sim.state();
  start.velocities = test::randomVectors(start.velocities.size(), 0.5);
  sim.restoreState(start);
  sim.advance(0.3);
  return sim.positions();
}

TEST(PbdSimulation, ParallelSolversGiveTheSameResultAtAnyThreadCount)
{
  for (PbdSolver solver : { PbdSolver::ParallelGaussSeidel, PbdSolver::Jacobi })
  {
    const std::vector<Vec3> one = runWithThreads(solver, 1);
    const std::vector<Vec3> two = runWithThreads(solver, 2);
    ASSERT_EQ(one.size(), two.size());
    for (std::size_t i = 0; i < one.size(); ++i)
    {
      ASSERT_EQ(one[i], two[i]) << "solver " << int(solver) << " point " << i; // bitwise
    }
  }
}

TEST(PbdSimulation, ColoringSeparatesConstraintsThatShareAParticle)
{
  PbdSettings settings;
  settings.solver = PbdSolver::ParallelGaussSeidel;
  ClothSpec spec;
  PbdSimulation cloth(makeCloth(spec), settings);
  EXPECT_LE(cloth.colorCount(), 12u); // a grid with diagonals has 8 neighbors per particle
  const DistanceBatch& links = cloth.links();
  const BatchSchedule schedule = makeSchedule(links, cloth.positions().size(), {});
  const Coloring& coloring = schedule.coloring;
  std::vector<int> seen(links.size(), 0);
  for (std::size_t k = 0; k < coloring.colorCount(); ++k)
  {
    std::vector<char> used(cloth.positions().size(), 0);
    for (auto c = coloring.colorOffsets[k]; c < coloring.colorOffsets[k + 1]; ++c)
    {
      const auto& e = links.ends[std::size_t(coloring.order[std::size_t(c)])];
      EXPECT_FALSE(used[std::size_t(e[0])] || used[std::size_t(e[1])]);
      used[std::size_t(e[0])] = used[std::size_t(e[1])] = 1;
      ++seen[std::size_t(coloring.order[std::size_t(c)])];
    }
  }
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int s) { return s == 1; }));
}

TEST(PbdSimulation, BreakableLinksBreakUnderAPullAndNeverAtRest)
{
  PbdSettings settings;
  settings.floorEnabled = true;
  settings.breakingStrain = 0.2;
  settings.links.compliance = 1e-3; // [m/N]: a 0.2 m box of water-like density sags ~6%
  settings.volumes.compliance = 1e-6;
  PbdSimulation resting(boxBody(4, 0.05), settings);
  resting.advance(2.0);
  EXPECT_EQ(resting.brokenLinkCount(), 0u);

  // The same links in a dense column (20x the density) hanging from its top face: its weight
  // pulls it apart.
  const TetMesh column = makeTetBox(1, 1, 6, 0.05, Vec3(0, 0, 1.0));
  Body bar;
  bar.mesh.points = column.points;
  bar.mesh.tets = column.tets;
  bar.material.physical.density = 20000.0;
  bar.pinned.assign(bar.mesh.points.size(), 0);
  for (std::size_t i = 0; i < bar.mesh.points.size(); ++i)
  {
    bar.pinned[i] = bar.mesh.points[i].z() > 1.3 - 1e-9;
  }
  settings.floorEnabled = false;
  PbdSimulation pulled(bar, settings);
  const DynamicState start = pulled.state();
  pulled.advance(1.0);
  EXPECT_GT(pulled.brokenLinkCount(), 0u);
  // The lower part fell away: the body fragmented.
  double lowest = 1.0;
  for (const Vec3& p : pulled.positions())
  {
    lowest = std::min(lowest, p.z());
  }
  EXPECT_LT(lowest, -1.0);
  // Broken state is part of the snapshot: restoring frame 0 heals the body.
  pulled.restoreState(start);
  EXPECT_EQ(pulled.brokenLinkCount(), 0u);
}

TEST(PbdSimulation, PlasticLinksKeepAPermanentStretch)
{
  // One link, one pinned end, the free end thrown outward: it swings out and back. Elastic, the
  // rest length stays 1; plastic, it flows past the yield band and stays longer.
  auto run = [](double yield, double breaking) {
    Body body;
    body.mesh.points = { Vec3(0, 0, 0), Vec3(1, 0, 0) };
    body.links = { { 0, 1 } };
    body.pointMass = { 1.0, 1.0 };
    body.pinned = { 1, 0 };
    PbdSettings s;
    s.gravity.setZero();
    s.links.compliance = 0.01;
    s.plasticYield = yield;
    s.plasticCreep = yield > 0 ? 50.0 : 0.0;
    s.breakingStrain = breaking;
    PbdSimulation sim(body, s);
    DynamicState start = sim.state();
    start.velocities[1] = Vec3(8.0, 0, 0);
    sim.restoreState(start);
    sim.advance(2.0);
    return std::make_pair(sim.links().rest[0], sim.brokenLinkCount());
  };
  const auto elastic = run(0.0, 10.0);
  EXPECT_DOUBLE_EQ(elastic.first, 1.0);
  const auto plastic = run(0.05, 10.0);
  EXPECT_GT(plastic.first, 1.1);
  EXPECT_EQ(plastic.second, 0u);
  const auto tearing = run(0.05, 0.3); // past the break limit it breaks
  EXPECT_EQ(tearing.second, 1u);
}

/// Length of a single link (rest length 1, unit masses, no gravity) stretched to 1.5 after one
/// step of the given settings.
double linkLengthAfterOneStep(PbdSettings settings)
{
  Body body;
  body.mesh.points = { Vec3(0, 0, 0), Vec3(1, 0, 0) };
  body.links = { { 0, 1 } };
  body.pointMass = { 1.0, 1.0 };
  settings.gravity.setZero();
  PbdSimulation sim(body, settings);
  DynamicState stretched = sim.state();
  stretched.positions[1].x() = 1.5;
  sim.restoreState(stretched);
  sim.advance(sim.stepSize());
  return (sim.positions()[1] - sim.positions()[0]).norm();
}

TEST(PbdSimulation, SorScalesEachProjectionByItsFactor)
{
  // One Gauss-Seidel projection of one link leaves C' = (1 - omega) C (omega = 1: satisfied,
  // 1.5: overshoots to -C/2, 0.5: halfway), for PBD at stiffness 1 and XPBD at compliance 0.
  for (PbdFormulation formulation : { PbdFormulation::Pbd, PbdFormulation::Xpbd })
  {
    for (double omega : { 0.5, 1.0, 1.5 })
    {
      PbdSettings settings;
      settings.formulation = formulation;
      settings.iterations = 1;
      settings.relaxation = omega;
      EXPECT_NEAR(linkLengthAfterOneStep(settings), 1.0 + (1.0 - omega) * 0.5, 1e-12) << omega;
    }
  }
}

TEST(PbdSimulation, StiffnessCorrectionMakesTheStepIndependentOfIterations)
{
  // PBD stiffness k = 0.5 over n iterations: each projection at k' = 1 - (1 - k)^(1/n) leaves
  // (1 - k')^n = 1 - k of the error after the step, whatever n: the stretch of 0.5 halves.
  for (int iterations : { 1, 4, 10 })
  {
    PbdSettings settings;
    settings.formulation = PbdFormulation::Pbd;
    settings.links.stiffness = 0.5;
    settings.iterations = iterations;
    EXPECT_NEAR(linkLengthAfterOneStep(settings), 1.25, 1e-12) << iterations << " iterations";
  }
}

TEST(PbdSimulation, JacobiMovesAParticleByTheRelaxedMeanOfItsCorrections)
{
  // Particle 1 between two pinned ones (rest: 0, 1, 2 on x), moved to x = 1.5: link 0-1 asks
  // -0.5, link 1-2 asks -0.5 too (all on particle 1); averaged Jacobi moves it by omega times
  // their mean, -0.5 omega (the plain sum would move it twice as far).
  for (double omega : { 1.0, 0.5 })
  {
    Body body;
    body.mesh.points = { Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0) };
    body.links = { { 0, 1 }, { 1, 2 } };
    body.pointMass = { 1.0, 1.0, 1.0 };
    body.pinned = { 1, 0, 1 };
    PbdSettings settings;
    settings.gravity.setZero();
    settings.solver = PbdSolver::Jacobi;
    settings.relaxation = omega;
    settings.iterations = 1;
    PbdSimulation sim(body, settings);
    DynamicState moved = sim.state();
    moved.positions[1].x() = 1.5;
    sim.restoreState(moved);
    sim.advance(sim.stepSize());
    EXPECT_NEAR(sim.positions()[1].x(), 1.5 - 0.5 * omega, 1e-12) << omega;
  }
}

TEST(PbdSimulation, PlasticFlowStopsAtTheYieldBandAndBreakingCountsFromTheOriginalLength)
{
  // One link of rest length 1 held at length L for one step (a compliance so large that the
  // projection does not move it, no gravity), creep x step = 1: the rest length flows to the
  // edge of the yield band, L -+ yield, in one step; a link breaks when |L - l0| passes the
  // breaking strain of its original length l0.
  auto afterOneStep = [](double length, double yield, double breaking) {
    Body body;
    body.mesh.points = { Vec3(0, 0, 0), Vec3(1, 0, 0) };
    body.links = { { 0, 1 } };
    body.pointMass = { 1.0, 1.0 };
    body.pinned = { 1, 1 }; // both held: the length stays L
    PbdSettings settings;
    settings.gravity.setZero();
    settings.links.compliance = 1e12;
    settings.plasticYield = yield;
    settings.plasticCreep = 1.0 / kDefaultPbdStep;
    settings.breakingStrain = breaking;
    PbdSimulation sim(body, settings);
    DynamicState held = sim.state();
    held.positions[1].x() = length;
    sim.restoreState(held);
    sim.advance(sim.stepSize());
    return std::make_pair(sim.links().rest[0], sim.brokenLinkCount());
  };
  EXPECT_NEAR(afterOneStep(1.5, 0.1, 0.0).first, 1.4, 1e-12);
  EXPECT_NEAR(afterOneStep(0.7, 0.1, 0.0).first, 0.8, 1e-12);
  EXPECT_NEAR(afterOneStep(1.05, 0.1, 0.0).first, 1.0, 1e-15); // inside the band: elastic
  EXPECT_EQ(afterOneStep(1.5, 0.0, 0.45).second, 1u);
  EXPECT_EQ(afterOneStep(1.5, 0.0, 0.55).second, 0u);
  // Flowed to 1.4 in the same step, the link still breaks against its original length.
  EXPECT_EQ(afterOneStep(1.5, 0.1, 0.45).second, 1u);
}

TEST(PbdSimulation, ResumingWithPlasticAndBrokenLinksReproducesTheRunExactly)
{
  // The dense column hanging from its top face, with plastic links that also break. Both
  // behaviours act (the run without either ends elsewhere), then a snapshot taken mid-run and
  // restored, in the same simulation and in a fresh one (as the frame cache does), continues
  // to the same bits, rest lengths and broken flags as the straight run.
  const TetMesh column = makeTetBox(1, 1, 6, 0.05, Vec3(0, 0, 1.0));
  Body bar;
  bar.mesh.points = column.points;
  bar.mesh.tets = column.tets;
  bar.material.physical.density = 20000.0;
  bar.pinned.assign(bar.mesh.points.size(), 0);
  for (std::size_t i = 0; i < bar.mesh.points.size(); ++i)
  {
    bar.pinned[i] = bar.mesh.points[i].z() > 1.3 - 1e-9;
  }
  PbdSettings settings;
  settings.links.compliance = 1e-3;
  settings.volumes.compliance = 1e-6;
  settings.plasticYield = 0.02;
  settings.plasticCreep = 5.0;
  settings.breakingStrain = 0.3;
  auto run = [&](const PbdSettings& s, double t) {
    PbdSimulation sim(bar, s);
    sim.advance(t);
    return sim.positions();
  };
  const std::vector<Vec3> reference = run(settings, 1.0);
  auto distance = [&](const std::vector<Vec3>& other) {
    double d = 0.0;
    for (std::size_t i = 0; i < other.size(); ++i)
    {
      d = std::max(d, (other[i] - reference[i]).norm());
    }
    return d;
  };
  PbdSettings elastic = settings;
  elastic.plasticYield = elastic.plasticCreep = 0.0;
  EXPECT_GT(distance(run(elastic, 1.0)), 1e-3);
  PbdSettings unbreakable = settings;
  unbreakable.breakingStrain = 0.0;
  EXPECT_GT(distance(run(unbreakable, 1.0)), 1e-2);

  PbdSimulation straight(bar, settings);
  straight.advance(0.5);
  straight.advance(1.0);
  PbdSimulation resumed(bar, settings);
  resumed.advance(0.5);
  const DynamicState snapshot = resumed.state();
  EXPECT_GT(resumed.brokenLinkCount(), 0u); // the snapshot holds broken links and plastic ones
  bool flowed = false;
  for (std::size_t c = 0; c < snapshot.linkRestLengths.size(); ++c)
  {
    flowed = flowed || std::abs(snapshot.linkRestLengths[c] - resumed.links().originalRest[c]) > 1e-3;
  }
  EXPECT_TRUE(flowed);
  resumed.advance(0.8);
  resumed.restoreState(snapshot);
  resumed.advance(1.0);
  PbdSimulation fresh(bar, settings);
  fresh.restoreState(snapshot);
  fresh.advance(1.0);
  for (const PbdSimulation* sim : { &resumed, &fresh })
  {
    EXPECT_EQ(sim->positions(), straight.positions());
    EXPECT_EQ(sim->velocities(), straight.velocities());
    EXPECT_EQ(sim->links().rest, straight.links().rest);
    EXPECT_EQ(sim->links().broken, straight.links().broken);
  }
  EXPECT_EQ(straight.positions(), reference);

  // A tet with a broken edge no longer holds its volume; the others still do.
  std::map<std::pair<std::int32_t, std::int32_t>, std::size_t> linkOf;
  for (std::size_t c = 0; c < straight.links().size(); ++c)
  {
    const auto& e = straight.links().ends[c];
    linkOf[{ std::min(e[0], e[1]), std::max(e[0], e[1]) }] = c;
  }
  std::size_t brokenTets = 0;
  for (std::size_t t = 0; t < straight.volumes().tets.size(); ++t)
  {
    const Tet& tet = straight.volumes().tets[t];
    bool hasBrokenEdge = false;
    for (int a = 0; a < 4; ++a)
    {
      for (int b = a + 1; b < 4; ++b)
      {
        hasBrokenEdge = hasBrokenEdge ||
          straight.links().broken[linkOf.at({ std::min(tet[a], tet[b]), std::max(tet[a], tet[b]) })];
      }
    }
    EXPECT_EQ(straight.volumes().broken[t] != 0, hasBrokenEdge) << "tet " << t;
    brokenTets += hasBrokenEdge;
  }
  EXPECT_GT(brokenTets, 0u);
  EXPECT_LT(brokenTets, straight.volumes().tets.size());
}

TEST(PbdSimulation, RestingBodyDoesNotGainEnergy)
{
  PbdSettings settings;
  settings.floorEnabled = true;
  settings.links.compliance = 1e-7;
  settings.volumes.compliance = 1e-9;
  PbdSimulation sim(boxBody(4, 0.05, Vec3(0, 0, 0.0)), settings);
  const std::vector<double> m = massesOf(sim);
  auto energy = [&] {
    double e = 0.0;
    for (std::size_t i = 0; i < m.size(); ++i)
    {
      e += 0.5 * m[i] * sim.velocities()[i].squaredNorm() + m[i] * 9.81 * sim.positions()[i].z();
    }
    return e;
  };
  const double start = energy();
  const double scale = 9.81 * sim.totalMass() * 0.2; // mg times the body height
  for (int frame = 1; frame <= 60; ++frame)
  {
    sim.advance(frame * 0.05);
    EXPECT_LE(energy(), start + 1e-9 * scale) << "t = " << sim.time();
  }
  // Still resting, not sunk: its bottom on the floor's contact margin.
  EXPECT_NEAR(centerOfMass(sim, m).z(), 0.1 + sim.collisionDetector()->margin(), 0.005);
}

TEST(PbdSimulation, ResidualToleranceStopsEarly)
{
  PbdSettings settings;
  settings.iterations = 200;
  settings.residualTolerance = 1e-6;
  settings.gravity.setZero();
  PbdSimulation sim(boxBody(3, 0.1), settings);
  DynamicState squashed = sim.state();
  squashed.positions = test::jitter(squashed.positions, 0.01);
  sim.restoreState(squashed);
  sim.advance(1.0 / 120.0);
  EXPECT_LT(sim.convergence().iterations, 200);
  EXPECT_LT(sim.convergence().residual, 1e-6);
  EXPECT_EQ(sim.convergence().residualHistory.size(), std::size_t(sim.convergence().iterations));
}

TEST(PbdSimulation, BadSettingsAndBodiesAreRefused)
{
  PbdSettings bad;
  bad.relaxation = 2.5;
  EXPECT_THROW(PbdSimulation(boxBody(1, 0.1), bad), InvalidInputError);
  PbdSettings good;
  Body linksWithoutMass;
  linksWithoutMass.mesh.points = { Vec3(0, 0, 0), Vec3(1, 0, 0) };
  linksWithoutMass.links = { { 0, 1 } };
  EXPECT_THROW(PbdSimulation(linksWithoutMass, good), InvalidInputError);
  Body coincident = linksWithoutMass;
  coincident.mesh.points[1] = coincident.mesh.points[0];
  coincident.pointMass = { 1, 1 };
  EXPECT_THROW(PbdSimulation(coincident, good), InvalidInputError);
  Body nothing;
  nothing.mesh.points = { Vec3(0, 0, 0) };
  EXPECT_THROW(PbdSimulation(nothing, good), InvalidInputError);
}

} // namespace
} // namespace softbody

namespace softbody
{
namespace
{
// XPBD with compliances from Young's modulus minimizes the mass-spring model's own elastic
// energy: a bar hanging from its top face must come to rest where the mass-spring bar does.
TEST(PbdSimulation, XpbdFromElasticityRestsWhereMassSpringRests)
{
  const TetMesh bar = makeTetBox(2, 2, 8, 0.025, Vec3(0, 0, 1.0));
  std::vector<char> top(bar.points.size(), 0);
  for (std::size_t i = 0; i < bar.points.size(); ++i)
  {
    top[i] = bar.points[i].z() > 1.2 - 1e-9;
  }
  const double E = 5.0e4, nu = 0.35, rho = 1000.0;

  Body springs;
  springs.mesh = bar;
  springs.pinned = top;
  springs.material.physical = { E, nu, rho, 5.0e-3 };
  MassSpringSimulation massSpring(springs, SceneSettings{});
  massSpring.advance(3.0);

  Body particles;
  particles.mesh.points = bar.points;
  particles.mesh.tets = bar.tets;
  particles.pinned = top;
  particles.material.physical = { E, nu, rho, 0.0 };
  PbdSettings settings;
  settings.elasticFromMaterial = true;
  settings.iterations = 20;
  settings.substeps = 4;
  settings.damping = 10.0;
  PbdSimulation xpbd(particles, settings);
  xpbd.advance(3.0);

  // The lowest point's sag: rho g L^2 / (2 E) ~ 4 mm for this bar.
  const std::size_t tip = 0; // (0, 0, 0) corner at the bottom
  const double sagSprings = bar.points[tip].z() - massSpring.positions()[tip].z();
  const double sagXpbd = bar.points[tip].z() - xpbd.positions()[tip].z();
  const double analytic = rho * 9.81 * 0.2 * 0.2 / (2 * E);
  std::printf("tip sag: mass-spring %.6f m, XPBD from elasticity %.6f m, rho g L^2 / 2E = %.6f m\n",
    sagSprings, sagXpbd, analytic);
  EXPECT_NEAR(sagXpbd / sagSprings, 1.0, 0.03);
  // Against elasticity: the spring network is stiffer than the continuum it stands for. The
  // measured model error, stated: mass-spring sags 0.777 of rho g L^2 / (2E) (3.047 mm against 3.924 mm), XPBD from the
  // same energy 0.769 (3.019 mm). A wrong factor in the stiffnesses, masses or gravity breaks the 3%.
  EXPECT_NEAR(sagSprings / analytic, 0.777, 0.03);
  EXPECT_NEAR(sagXpbd / analytic, 0.769, 0.03);
}
} // namespace
} // namespace softbody

namespace softbody
{
namespace
{
// A cantilever (0.2 m long, 5 x 5 cm, clamped at x = 0) sagging under its own weight, against
// beam theory: Euler-Bernoulli q L^4 / (8 E I) = 3 rho g L^4 / (2 E a^2) = 9.42 mm plus
// Timoshenko's shear term rho g L^2 / (2 kappa G) = 0.64 mm, 10.05 mm in all (E = 1 MPa,
// nu = 0.35). The spring network is stiffer in bending than the continuum: measured, the mean
// tip sag is 0.608 of the beam value for mass-spring (averaged over two periods of the first
// bending mode, which its light damping has not yet stopped) and 0.608 for XPBD from the same
// energy. The bound (+-0.03) is the measured model error's, not elasticity's.
TEST(PbdSimulation, CantileverSagAgainstBeamTheoryForEachMethod)
{
  const double E = 1.0e6, nu = 0.35, rho = 1000.0, L = 0.2, a = 0.05, g = 9.81;
  const TetMesh bar = makeTetBox(8, 2, 2, 0.025, Vec3(0, 0, 1.0));
  std::vector<char> clamped(bar.points.size(), 0);
  std::vector<std::size_t> tip;
  for (std::size_t i = 0; i < bar.points.size(); ++i)
  {
    clamped[i] = bar.points[i].x() < 1e-9;
    if (bar.points[i].x() > L - 1e-9)
    {
      tip.push_back(i);
    }
  }
  const double shearModulus = E / (2.0 * (1.0 + nu));
  const double beam = 3.0 * rho * g * std::pow(L, 4) / (2.0 * E * a * a) +
    rho * g * L * L / (2.0 * (5.0 / 6.0) * shearModulus);
  auto tipSag = [&](const std::vector<Vec3>& x) {
    double sag = 0.0;
    for (std::size_t i : tip)
    {
      sag += bar.points[i].z() - x[i].z();
    }
    return sag / double(tip.size());
  };

  Body springs;
  springs.mesh = bar;
  springs.pinned = clamped;
  springs.material.physical = { E, nu, rho, 1.0e-3 };
  MassSpringSimulation massSpring(springs, SceneSettings{});
  massSpring.advance(3.0);
  double meanSag = 0.0;
  for (int k = 1; k <= 40; ++k) // 0.32 s: two periods of the first mode (40 rad/s)
  {
    massSpring.advance(3.0 + 0.008 * k);
    meanSag += tipSag(massSpring.positions()) / 40.0;
  }

  Body particles;
  particles.mesh.points = bar.points;
  particles.mesh.tets = bar.tets;
  particles.pinned = clamped;
  particles.material.physical = { E, nu, rho, 0.0 };
  PbdSettings settings;
  settings.elasticFromMaterial = true;
  settings.iterations = 20;
  settings.substeps = 4;
  settings.damping = 10.0;
  PbdSimulation xpbd(particles, settings);
  xpbd.advance(3.0);
  const double xpbdSag = tipSag(xpbd.positions());

  std::printf("cantilever tip sag: mass-spring %.6f m, XPBD %.6f m, beam theory %.6f m\n", meanSag,
    xpbdSag, beam);
  EXPECT_NEAR(meanSag / beam, 0.608, 0.03);
  EXPECT_NEAR(xpbdSag / beam, 0.608, 0.03);
}
} // namespace
} // namespace softbody
