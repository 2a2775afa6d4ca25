// The four-lane kernels (common/simd.h) against the one-element-at-a-time ones:
//   - XPBD links and tet volumes, swept color by color: positions and multipliers equal bit for
//     bit to projecting each constraint alone with the scalar kernel (pbd_kernels.h), at every
//     SimdLevel this CPU runs, with broken, pinned, zero-stiffness and compliant constraints
//     and ranges that end in a partial block; and the same at 1 and 2 threads;
//   - mass-spring forces: equal to rounding to the textbook formulas (unit normals, gradients
//     from geometry.h), bitwise equal at every SimdLevel and at 1 and 2 threads.
#include "softbody/massspring/mass_spring_forces.h"
#include "softbody/mesh/graph_coloring.h"
#include "softbody/mesh/mesh_generators.h"
#include "softbody/mesh/topology.h"
#include "softbody/pbd/pbd_solvers.h"
#include "test_support.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cstring>
#include <numeric>

using namespace softbody;

namespace
{

std::vector<SimdLevel> levelsThisCpuRuns()
{
  std::vector<SimdLevel> levels = { SimdLevel::Baseline };
  if (bestSimdLevel() == SimdLevel::Avx2)
  {
    levels.push_back(SimdLevel::Avx2);
  }
  return levels;
}

bool bitwiseEqual(const std::vector<double>& a, const std::vector<double>& b)
{
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

/// A jittered box with both batches stored color by color, as the parallel solver stores them.
/// The origin is off zero so no coordinate is exactly zero.
struct ColoredBody
{
  std::vector<Vec3> x;
  std::vector<double> w;
  DistanceBatch links;
  VolumeBatch volumes;
  BatchSchedule linkSchedule;
  BatchSchedule volumeSchedule;
};

ProjectionParameters parametersOf(std::size_t c)
{
  ProjectionParameters p;
  p.scale = c % 11 == 5 ? 0.0 : (c % 3 == 0 ? 1.0 : 0.8); // zero stiffness, rigid, relaxed
  p.alphaTilde = c % 4 == 0 ? 0.0 : 1e-3 * double(c % 7);
  return p;
}

template <class Batch>
BatchSchedule storeByColor(Batch& batch, std::size_t particleCount, const std::vector<char>& movable)
{
  BatchSchedule schedule;
  schedule.coloring = colorConstraints(particleCount, flattenParticles(batch), Batch::Arity, movable);
  batch.storeInOrder(schedule.coloring.order);
  std::iota(schedule.coloring.order.begin(), schedule.coloring.order.end(), 0);
  schedule.storedByColor = true;
  return schedule;
}

ColoredBody makeColoredBody(int n, DistanceKind kind)
{
  const TetMesh mesh = makeTetBox(n, n + 1, n - 1, 0.01, Vec3(0.0031, 0.0017, 0.0023));
  const Topology topology = buildTopology(mesh.points.size(), mesh.tets);
  ColoredBody body;
  body.x = test::jitter(mesh.points, 2e-3, 5);
  const std::size_t particles = mesh.points.size();
  body.w.resize(particles);
  std::vector<char> movable(particles);
  for (std::size_t i = 0; i < particles; ++i)
  {
    body.w[i] = i % 7 == 3 ? 0.0 : 0.5 + 0.1 * double(i % 13); // some pinned
    movable[i] = body.w[i] > 0.0 ? 1 : 0;
  }
  body.links.kind = kind;
  for (std::size_t e = 0; e < topology.edges.size(); ++e)
  {
    const Edge& edge = topology.edges[e];
    body.links.ends.push_back({ edge.a, edge.b });
    body.links.rest.push_back((mesh.points[edge.a] - mesh.points[edge.b]).norm());
    body.links.broken.push_back(e % 13 == 4 ? 1 : 0);
    body.links.lambda.push_back(1e-4 * double(e % 5));
    body.links.params.push_back(parametersOf(e));
  }
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
  {
    const Tet& tet = mesh.tets[t];
    body.volumes.tets.push_back(tet);
    body.volumes.restVolume.push_back(
      signedTetVolume(mesh.points[tet[0]], mesh.points[tet[1]], mesh.points[tet[2]], mesh.points[tet[3]]));
    body.volumes.broken.push_back(t % 17 == 2 ? 1 : 0);
    body.volumes.lambda.push_back(-1e-9 * double(t % 3));
    body.volumes.params.push_back(parametersOf(t));
  }
  body.linkSchedule = storeByColor(body.links, particles, movable);
  body.volumeSchedule = storeByColor(body.volumes, particles, movable);
  return body;
}

/// Sweeps a batch color by color, each color's range either one constraint at a time with the
/// scalar kernel or with the wide kernel at `level`.
template <class Batch>
void sweepColors(Batch& batch, const BatchSchedule& schedule, std::vector<Vec3>& x, const std::vector<double>& w,
  bool wide, SimdLevel level)
{
  const Coloring& coloring = schedule.coloring;
  for (std::size_t color = 0; color < coloring.colorCount(); ++color)
  {
    const auto begin = static_cast<std::size_t>(coloring.colorOffsets[color]);
    const auto end = static_cast<std::size_t>(coloring.colorOffsets[color + 1]);
    if (!wide)
    {
      for (std::size_t c = begin; c < end; ++c)
      {
        detail::projectAndApply(batch, c, x, w);
      }
    }
    else if constexpr (std::is_same_v<Batch, DistanceBatch>)
    {
      projectLinksWide(batch, begin, end, x, w, level);
    }
    else
    {
      projectVolumesWide(batch, begin, end, x, w, level);
    }
  }
}

template <class Batch>
void expectWideEqualsScalar(Batch ColoredBody::*member, const BatchSchedule ColoredBody::*schedule, DistanceKind kind)
{
  const ColoredBody start = makeColoredBody(7, kind);
  ColoredBody scalar = start;
  for (int sweep = 0; sweep < 3; ++sweep)
  {
    sweepColors(scalar.*member, scalar.*schedule, scalar.x, scalar.w, false, SimdLevel::Baseline);
  }
  // Not a test of nothing: the sweeps moved the body and reduced the constraint error.
  EXPECT_GT(test::maxDistance(scalar.x, start.x), 1e-5);
  EXPECT_LT(squaredResidual(scalar.*member, scalar.x, scalar.w), 0.5 * squaredResidual(start.*member, start.x, start.w));
  for (SimdLevel level : levelsThisCpuRuns())
  {
    ColoredBody wide = start;
    for (int sweep = 0; sweep < 3; ++sweep)
    {
      sweepColors(wide.*member, wide.*schedule, wide.x, wide.w, true, level);
    }
    EXPECT_TRUE(test::bitwiseEqual(wide.x, scalar.x))
      << simdLevelName(level) << ": positions differ by up to " << test::maxDistance(wide.x, scalar.x) << " m";
    EXPECT_TRUE(bitwiseEqual((wide.*member).lambda, (scalar.*member).lambda)) << simdLevelName(level);
  }
}

std::vector<Vec3> coloredSweepsWithThreads(std::size_t threads)
{
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  // Large enough that colors hold several chunks of 256 constraints.
  ColoredBody body = makeColoredBody(14, DistanceKind::Equality);
  for (int sweep = 0; sweep < 3; ++sweep)
  {
    coloredGaussSeidelSweep(body.links, body.linkSchedule, body.x, body.w);
    coloredGaussSeidelSweep(body.volumes, body.volumeSchedule, body.x, body.w);
  }
  return body.x;
}

/// Sequential Gauss-Seidel with the wide kernels on the independent blocks against the scalar
/// sweep, over the batches in color order or in four interleaved streams of it.
void expectSequentialWideEqualsScalar(DistanceKind kind, bool streams)
{
  const ColoredBody start = makeColoredBody(7, kind);
  ColoredBody body = start;
  auto reorder = [&](auto& batch) {
    if (!streams)
    {
      return;
    }
    batch.storeInOrder(interleavedStreams(batch.size()));
  };
  reorder(body.links);
  reorder(body.volumes);
  const std::vector<char> linkBlocks = independentBlocks(body.links);
  const std::vector<char> volumeBlocks = independentBlocks(body.volumes);
  // Both paths run: blocks of lanes, and (color order: pinned particles shared) blocks one
  // constraint at a time.
  for (const std::vector<char>* blocks : { &linkBlocks, &volumeBlocks })
  {
    EXPECT_GT(std::count(blocks->begin(), blocks->end(), 1), 0);
    if (!streams)
    {
      EXPECT_GT(std::count(blocks->begin(), blocks->end(), 0), 0);
    }
  }
  ColoredBody scalar = body;
  for (int sweep = 0; sweep < 3; ++sweep)
  {
    gaussSeidelSweep(scalar.links, scalar.x, scalar.w);
    gaussSeidelSweep(scalar.volumes, scalar.x, scalar.w);
  }
  EXPECT_GT(test::maxDistance(scalar.x, body.x), 1e-5);
  for (SimdLevel level : levelsThisCpuRuns())
  {
    ColoredBody wide = body;
    for (int sweep = 0; sweep < 3; ++sweep)
    {
      gaussSeidelLinksWide(wide.links, linkBlocks, wide.x, wide.w, level);
      gaussSeidelVolumesWide(wide.volumes, volumeBlocks, wide.x, wide.w, level);
    }
    EXPECT_TRUE(test::bitwiseEqual(wide.x, scalar.x))
      << simdLevelName(level) << ": positions differ by up to " << test::maxDistance(wide.x, scalar.x) << " m";
    EXPECT_TRUE(bitwiseEqual(wide.links.lambda, scalar.links.lambda)) << simdLevelName(level);
    EXPECT_TRUE(bitwiseEqual(wide.volumes.lambda, scalar.volumes.lambda)) << simdLevelName(level);
  }
}

} // namespace

TEST(WideKernels, SequentialGaussSeidelWithIndependentBlocksEqualsTheScalarSweepBitForBit)
{
  // Color order: consecutive constraints of one color share no movable particle but may share
  // pinned ones (those blocks run one at a time); streams: interleaved as PbdSimulation stores
  // Gauss-Seidel's batches.
  for (bool streams : { false, true })
  {
    expectSequentialWideEqualsScalar(DistanceKind::Equality, streams);
    expectSequentialWideEqualsScalar(DistanceKind::AtLeast, streams);
  }
}

TEST(WideKernels, IndependentBlocksFlagEveryBlockWithASharedParticle)
{
  DistanceBatch links;
  // Blocks: {0-1, 2-3, 4-5, 6-7} independent; {0-1, 1-2, 3-4, 5-6} shares 1; {8-9} partial.
  for (const std::array<std::int32_t, 2> e : { std::array<std::int32_t, 2>{ 0, 1 }, { 2, 3 }, { 4, 5 }, { 6, 7 },
         { 0, 1 }, { 1, 2 }, { 3, 4 }, { 5, 6 }, { 8, 9 } })
  {
    links.ends.push_back(e);
  }
  EXPECT_EQ(independentBlocks(links), (std::vector<char>{ 1, 0 }));
}

TEST(WideKernels, ColoredLinkSweepsEqualTheScalarKernelBitForBit)
{
  expectWideEqualsScalar(&ColoredBody::links, &ColoredBody::linkSchedule, DistanceKind::Equality);
  expectWideEqualsScalar(&ColoredBody::links, &ColoredBody::linkSchedule, DistanceKind::AtLeast);
}

TEST(WideKernels, ColoredVolumeSweepsEqualTheScalarKernelBitForBit)
{
  expectWideEqualsScalar(&ColoredBody::volumes, &ColoredBody::volumeSchedule, DistanceKind::Equality);
}

TEST(WideKernels, ColoredSweepsAreTheSameAtOneAndTwoThreads)
{
  const std::vector<Vec3> one = coloredSweepsWithThreads(1);
  const std::vector<Vec3> two = coloredSweepsWithThreads(2);
  EXPECT_TRUE(test::bitwiseEqual(one, two)) << "differ by up to " << test::maxDistance(one, two) << " m";
}

TEST(WideKernels, TetVolumeKernelEqualsTheGeometryGradientsToRounding)
{
  // The kernel folds the gradients' 1/6 into its multiplier; the textbook form divides each.
  const std::vector<Vec3> x = test::jitter({ Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1) }, 0.2, 3);
  const std::array<double, 4> w = { 1.0, 0.5, 2.0, 0.0 };
  ProjectionParameters p;
  p.scale = 0.9;
  p.alphaTilde = 0.01;
  const double rest = 0.1, lambda = 0.02;
  const Projection<4> kernel = projectTetVolume({ x[0], x[1], x[2], x[3] }, w, rest, lambda, p);
  const auto g = tetVolumeGradients(x[0], x[1], x[2], x[3]);
  double weighted = 0.0;
  for (int k = 0; k < 4; ++k)
  {
    weighted += w[static_cast<std::size_t>(k)] * g[static_cast<std::size_t>(k)].squaredNorm();
  }
  const double residual = signedTetVolume(x[0], x[1], x[2], x[3]) - rest + p.alphaTilde * lambda;
  const double dLambda = -p.scale * residual / (weighted + p.alphaTilde);
  EXPECT_NEAR(kernel.residual, residual, 1e-14);
  EXPECT_NEAR(kernel.dLambda, dLambda, 1e-13 * std::abs(dLambda));
  for (std::size_t k = 0; k < 4; ++k)
  {
    EXPECT_LT((kernel.dx[k] - w[k] * dLambda * g[k]).norm(), 1e-13 * std::abs(dLambda) * g[k].norm() + 1e-300);
  }
  EXPECT_EQ(kernel.dx[3], Vec3::Zero()); // pinned corner
}

namespace
{

struct SpringBody
{
  Topology topology;
  ElementConstants constants;
  std::vector<Vec3> x, v;
};

SpringBody makeSpringBody(int n)
{
  TetMesh mesh = makeTetBox(n, n + 1, n - 1, 0.01, Vec3(0.001, 0.002, 0.003));
  mesh.tets.resize(mesh.tets.size() - 3); // element counts that end in a partial block
  SpringBody body;
  body.topology = buildTopology(mesh.points.size(), mesh.tets);
  MaterialSettings material;
  material.physical.poissonRatio = 0.45;
  material.physical.dampingTime = 1e-3;
  std::vector<std::string> warnings;
  body.constants = computeElementConstants(body.topology, mesh.points, material, warnings);
  body.x = test::jitter(mesh.points, 1.5e-3, 9);
  body.v = test::randomVectors(mesh.points.size(), 0.3, 4);
  return body;
}

/// The textbook forces: unit normals, gradients as geometry.h computes them.
std::vector<Vec3> referenceForces(const SpringBody& body)
{
  const Topology& topology = body.topology;
  const ElementConstants& c = body.constants;
  std::vector<Vec3> f(topology.vertexCount, Vec3::Zero());
  for (std::size_t e = 0; e < topology.edges.size(); ++e)
  {
    const Edge& edge = topology.edges[e];
    const Vec3 d = body.x[edge.a] - body.x[edge.b];
    const Vec3 n = d.normalized();
    const Vec3 fa = -(c.springStiffness[e] * (d.norm() - c.restLength[e]) +
                      c.springDamping[e] * n.dot(body.v[edge.a] - body.v[edge.b])) * n;
    f[edge.a] += fa;
    f[edge.b] -= fa;
  }
  for (std::size_t t = 0; t < topology.tets.size(); ++t)
  {
    const Tet& tet = topology.tets[t];
    const auto g = tetVolumeGradients(body.x[tet[0]], body.x[tet[1]], body.x[tet[2]], body.x[tet[3]]);
    const double volume = signedTetVolume(body.x[tet[0]], body.x[tet[1]], body.x[tet[2]], body.x[tet[3]]);
    double rate = 0.0;
    for (std::size_t k = 0; k < 4; ++k)
    {
      rate += g[k].dot(body.v[tet[k]]);
    }
    const double s = -(c.volumeStiffness[t] * (volume - c.restVolume[t]) + c.volumeDamping[t] * rate);
    for (std::size_t k = 0; k < 4; ++k)
    {
      f[tet[k]] += s * g[k];
    }
  }
  return f;
}

std::vector<Vec3> forcesWith(const SpringBody& body, SimdLevel level, std::size_t threads)
{
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  ForceScratch scratch;
  std::vector<Vec3> f;
  computeInternalForces(body.topology, body.constants, body.x, body.v, scratch, f, level);
  return f;
}

} // namespace

TEST(WideKernels, MassSpringForcesEqualTheTextbookFormulasToRounding)
{
  const SpringBody body = makeSpringBody(12);
  ASSERT_TRUE(body.constants.hasVolumeTerm);
  ASSERT_NE(body.topology.edges.size() % 4, 0u);
  ASSERT_NE(body.topology.tets.size() % 4, 0u);
  const std::vector<Vec3> reference = referenceForces(body);
  double largest = 0.0;
  for (const Vec3& f : reference)
  {
    largest = std::max(largest, f.norm());
  }
  ASSERT_GT(largest, 0.0);
  const std::vector<Vec3> baseline = forcesWith(body, SimdLevel::Baseline, 1);
  EXPECT_LT(test::maxDistance(baseline, reference), 1e-12 * largest);
  for (SimdLevel level : levelsThisCpuRuns())
  {
    for (std::size_t threads : { 1u, 2u })
    {
      EXPECT_TRUE(test::bitwiseEqual(forcesWith(body, level, threads), baseline))
        << simdLevelName(level) << ", " << threads << " thread(s)";
    }
  }
}
