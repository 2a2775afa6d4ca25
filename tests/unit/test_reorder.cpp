// Renumbering for locality (mesh/reorder.h) and the steppers built on renumbered bodies: the
// orders are permutations, every output comes back in the input's order and equals the run on
// the body as given (bit for bit where the arithmetic order is unchanged, otherwise within
// rounding), snapshots resume exactly, and the result does not depend on the thread count.
#include "test_support.h"

#include "softbody/common/errors.h"
#include "softbody/massspring/mass_spring_reordered.h"
#include "softbody/mesh/mesh_generators.h"
#include "softbody/mesh/reorder.h"
#include "softbody/mesh/topology.h"
#include "softbody/pbd/cloth.h"
#include "softbody/pbd/pbd_reordered.h"
#include "softbody/pbd/pbd_simulation.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cstring>
#include <numeric>
#include <random>

using namespace softbody;

namespace
{

/// A box mesh with its points and tets shuffled (as a mesher might hand them over), slightly
/// jittered so no two points share a Morton cell by symmetry alone.
TetMesh shuffledBox(int n, unsigned seed = 3)
{
  TetMesh box = makeTetBox(n, n, n, 0.01, Vec3(0, 0, 0.05));
  std::mt19937 rng(seed);
  Order order(box.points.size());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  const Order slot = inverseOrder(order);
  TetMesh mesh;
  mesh.points = test::jitter(toStorageOrder(box.points, order), 1e-4);
  for (Tet t : box.tets)
  {
    for (std::int32_t& v : t)
    {
      v = slot[static_cast<std::size_t>(v)];
    }
    mesh.tets.push_back(t);
  }
  std::shuffle(mesh.tets.begin(), mesh.tets.end(), rng);
  return mesh;
}

/// Largest |slot[a] - slot[b]| over the edges: the matrix bandwidth of a vertex order.
std::int32_t bandwidth(const TetMesh& mesh, const Order& slot)
{
  std::int32_t widest = 0;
  for (const Edge& e : extractUniqueEdges(mesh.tets))
  {
    const std::int32_t a = slot.empty() ? e.a : slot[static_cast<std::size_t>(e.a)];
    const std::int32_t b = slot.empty() ? e.b : slot[static_cast<std::size_t>(e.b)];
    widest = std::max(widest, std::abs(a - b));
  }
  return widest;
}

Body bodyOf(const TetMesh& mesh)
{
  Body body;
  body.mesh = mesh;
  body.material.physical.youngsModulus = 2e4;
  // Pin the points of the top layer: pins must follow their points through the renumbering.
  body.pinned.assign(mesh.points.size(), 0);
  double top = -1e300;
  for (const Vec3& p : mesh.points)
  {
    top = std::max(top, p.z());
  }
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
  {
    body.pinned[i] = mesh.points[i].z() > top - 1e-3 ? 1 : 0;
  }
  return body;
}

SceneSettings sceneWithFloor()
{
  SceneSettings scene;
  scene.floorEnabled = true;
  scene.floor.origin = Vec3(0, 0, 0.049);
  return scene;
}

} // namespace

TEST(Reorder, OrdersArePermutations)
{
  const TetMesh mesh = shuffledBox(6);
  const std::size_t n = mesh.points.size();
  for (VertexOrdering ordering :
    { VertexOrdering::Input, VertexOrdering::Morton, VertexOrdering::ReverseCuthillMcKee })
  {
    const Reordering r = computeReordering(ordering, mesh.points, mesh.tets, {}, true);
    EXPECT_TRUE(isPermutation(r.vertexOrder, n)) << vertexOrderingName(ordering);
    EXPECT_TRUE(isPermutation(r.tetOrder, mesh.tets.size())) << vertexOrderingName(ordering);
    for (std::size_t i = 0; i < n; ++i)
    {
      ASSERT_EQ(r.vertexOrder[static_cast<std::size_t>(r.vertexSlot[i])], static_cast<std::int32_t>(i));
    }
    // The reordered tets are the input's tets, renumbered: same corners in the same order.
    const std::vector<Tet> stored = reorderTets(mesh.tets, r);
    for (std::size_t t = 0; t < stored.size(); ++t)
    {
      const Tet& original = mesh.tets[static_cast<std::size_t>(r.tetOrder[t])];
      for (int c = 0; c < 4; ++c)
      {
        ASSERT_EQ(stored[t][c], r.vertexSlot[static_cast<std::size_t>(original[c])]);
      }
    }
  }
  // Vertices in no tet, and a mesh with several components, are still numbered once each.
  TetMesh two = makeTetBox(2, 2, 2, 0.01);
  const std::size_t firstCount = two.points.size();
  const TetMesh other = makeTetBox(2, 2, 2, 0.01, Vec3(1, 0, 0));
  for (const Vec3& p : other.points)
  {
    two.points.push_back(p);
  }
  for (Tet t : other.tets)
  {
    for (std::int32_t& v : t)
    {
      v += static_cast<std::int32_t>(firstCount);
    }
    two.tets.push_back(t);
  }
  two.points.emplace_back(5, 5, 5); // unused
  EXPECT_TRUE(isPermutation(reverseCuthillMcKeeOrder(two.points.size(), two.tets), two.points.size()));
  EXPECT_TRUE(isPermutation(mortonOrder(two.points), two.points.size()));
  EXPECT_EQ(reverseCuthillMcKeeOrder(two.points.size(), two.tets).back(),
    static_cast<std::int32_t>(two.points.size() - 1));
  EXPECT_FALSE(isPermutation({ 0, 0, 1 }, 3));
  EXPECT_FALSE(isPermutation({ 0, 3, 1 }, 3));
}

TEST(Reorder, BothOrdersBringNeighboursTogether)
{
  const TetMesh mesh = shuffledBox(8);
  const std::int32_t shuffled = bandwidth(mesh, {});
  const std::int32_t rcm =
    bandwidth(mesh, inverseOrder(reverseCuthillMcKeeOrder(mesh.points.size(), mesh.tets)));
  const std::int32_t morton = bandwidth(mesh, inverseOrder(mortonOrder(mesh.points)));
  // A 9^3-point box: RCM's bandwidth is about one layer (~2 x 81), a shuffle's nearly n.
  EXPECT_LT(rcm, 200);
  EXPECT_LT(rcm, shuffled / 3);
  EXPECT_LT(morton, shuffled);
}

TEST(Reorder, MassSpringOutputsInInputOrderEqualTheRunAsGiven)
{
  const TetMesh mesh = shuffledBox(5);
  const Body body = bodyOf(mesh);
  const SceneSettings scene = sceneWithFloor();
  std::unique_ptr<Simulation> given = makeMassSpringSimulation(body, scene, VertexOrdering::Input);
  const double end = 60 * given->stepSize();
  given->advance(end);
  for (VertexOrdering ordering : { VertexOrdering::Morton, VertexOrdering::ReverseCuthillMcKee })
  {
    std::unique_ptr<Simulation> reordered = makeMassSpringSimulation(body, scene, ordering);
    ASSERT_NE(dynamic_cast<ReorderedSimulation*>(reordered.get()), nullptr);
    EXPECT_TRUE(test::bitwiseEqual(reordered->restPositions(), mesh.points));
    // The stability bound sums over each vertex's elements in another order: rounding.
    EXPECT_NEAR(reordered->stepSize(), given->stepSize(), 1e-14 * given->stepSize());
    EXPECT_NEAR(reordered->totalMass(), given->totalMass(), 1e-15 * given->totalMass());
    for (std::size_t i = 0; i < mesh.points.size(); ++i)
    {
      ASSERT_NEAR(reordered->inverseMasses()[i], given->inverseMasses()[i], 1e-12 * given->inverseMasses()[i])
        << "point " << i;
    }
    reordered->advance(end);
    EXPECT_EQ(reordered->stepCount(), given->stepCount());
    // Only the summation order of each vertex's springs and tets differs: rounding.
    EXPECT_LT(test::maxDistance(reordered->positions(), given->positions()), 1e-12);
    EXPECT_LT(test::maxDistance(reordered->velocities(), given->velocities()), 1e-9);
    EXPECT_GT(test::maxDistance(given->positions(), mesh.points), 1e-5); // it did move
    for (std::size_t i = 0; i < mesh.points.size(); ++i)
    {
      if (body.pinned[i])
      {
        ASSERT_TRUE(reordered->positions()[i] == mesh.points[i]) << "pinned point " << i << " moved";
      }
    }
    const std::vector<double> a = given->tetVolumeRatios(), b = reordered->tetVolumeRatios();
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t t = 0; t < a.size(); ++t)
    {
      ASSERT_NEAR(a[t], b[t], 1e-9) << "tet " << t;
    }
  }
}

TEST(Reorder, MassSpringSnapshotsInInputOrderResumeExactly)
{
  const Body body = bodyOf(shuffledBox(4));
  std::unique_ptr<Simulation> sim = makeMassSpringSimulation(body, sceneWithFloor());
  const double h = sim->stepSize();
  sim->advance(20 * h);
  const DynamicState snapshot = sim->state();
  sim->advance(50 * h);
  const DynamicState straight = sim->state();
  sim->restoreState(snapshot);
  EXPECT_TRUE(test::bitwiseEqual(sim->positions(), snapshot.positions));
  sim->advance(50 * h);
  EXPECT_TRUE(test::bitwiseEqual(sim->positions(), straight.positions));
  EXPECT_TRUE(test::bitwiseEqual(sim->velocities(), straight.velocities));

  // A snapshot restored into a second stepper of the same body continues the same way.
  std::unique_ptr<Simulation> other = makeMassSpringSimulation(body, sceneWithFloor());
  other->restoreState(snapshot);
  other->advance(50 * h);
  EXPECT_TRUE(test::bitwiseEqual(other->positions(), straight.positions));
}

TEST(Reorder, MassSpringReorderedRunIsTheSameAtAnyThreadCount)
{
  const Body body = bodyOf(shuffledBox(9)); // enough vertices to split across tasks
  std::vector<std::vector<Vec3>> results;
  for (int threads : { 1, 2, 3 })
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    std::unique_ptr<Simulation> sim = makeMassSpringSimulation(body, sceneWithFloor());
    sim->advance(40 * sim->stepSize());
    results.push_back(sim->positions());
  }
  EXPECT_TRUE(test::bitwiseEqual(results[0], results[1]));
  EXPECT_TRUE(test::bitwiseEqual(results[0], results[2]));
}

TEST(Reorder, InvalidBodiesAreRefusedWithTheInputsOwnMessage)
{
  TetMesh mesh = shuffledBox(3);
  mesh.tets[5] = { mesh.tets[5][0], mesh.tets[5][1], mesh.tets[5][2], 100000 };
  Body body = bodyOf(mesh);
  std::string plain, reordered;
  try
  {
    makeMassSpringSimulation(body, sceneWithFloor(), VertexOrdering::Input);
  }
  catch (const InvalidInputError& error)
  {
    plain = error.what();
  }
  try
  {
    makeMassSpringSimulation(body, sceneWithFloor(), VertexOrdering::Morton);
  }
  catch (const InvalidInputError& error)
  {
    reordered = error.what();
  }
  EXPECT_FALSE(plain.empty());
  EXPECT_EQ(plain, reordered);

  // An inverted tet is named by its input cell, re-oriented either way.
  TetMesh inverted = shuffledBox(3);
  std::swap(inverted.tets[7][0], inverted.tets[7][1]);
  std::unique_ptr<Simulation> a = makeMassSpringSimulation(bodyOf(inverted), sceneWithFloor(), VertexOrdering::Input);
  std::unique_ptr<Simulation> b = makeMassSpringSimulation(bodyOf(inverted), sceneWithFloor(), VertexOrdering::Morton);
  EXPECT_EQ(a->warnings(), b->warnings());
  ASSERT_FALSE(b->warnings().empty());
  EXPECT_NE(b->warnings()[0].find("cell 7"), std::string::npos) << b->warnings()[0];
}

TEST(Reorder, MassSpringRefusesTheParticleEnginesPartsNamingThem)
{
  // One Body type serves every method; the mass-spring model reads tets only, so links or
  // per-point masses it would ignore are refused rather than dropped.
  Body body = bodyOf(shuffledBox(2));
  body.links = { { 0, 1 }, { 1, 2 } };
  body.pointMass = std::vector<double>(body.mesh.points.size(), 1.0);
  for (VertexOrdering ordering : { VertexOrdering::Input, VertexOrdering::Morton })
  {
    try
    {
      makeMassSpringSimulation(body, sceneWithFloor(), ordering);
      FAIL() << "a body with links was accepted";
    }
    catch (const InvalidInputError& error)
    {
      const std::string message = error.what();
      EXPECT_NE(message.find("2 links"), std::string::npos) << message;
      EXPECT_NE(message.find("point masses"), std::string::npos) << message;
      EXPECT_NE(message.find("PBD or XPBD"), std::string::npos) << message;
    }
  }
}

TEST(Reorder, PbdLinkBodiesAreBitwiseEqualToTheRunAsGiven)
{
  // Links keep their order (only their ends are renumbered), so Gauss-Seidel projects the same
  // constraints in the same order on the same numbers: the same result bit for bit.
  ClothSpec spec;
  spec.particlesAlong1 = spec.particlesAlong2 = 12;
  Body body = makeCloth(spec);
  // Shuffle the particles, as an input might come.
  std::mt19937 rng(5);
  Order order(body.mesh.points.size());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  Reordering shuffle;
  shuffle.vertexOrder = order;
  shuffle.vertexSlot = inverseOrder(order);
  body = reorderBody(body, shuffle);
  for (PbdSolver solver : { PbdSolver::GaussSeidel, PbdSolver::ParallelGaussSeidel })
  {
    PbdSettings settings;
    settings.solver = solver;
    settings.floorEnabled = true;
    settings.floor.origin = Vec3(0, 0, -0.3);
    std::unique_ptr<Simulation> given = makePbdSimulation(body, settings, VertexOrdering::Input);
    PbdSimulation* inner = nullptr;
    std::unique_ptr<Simulation> reordered = makePbdSimulation(body, settings, VertexOrdering::Morton, &inner);
    ASSERT_NE(inner, nullptr);
    given->advance(0.5);
    reordered->advance(0.5);
    if (solver == PbdSolver::GaussSeidel)
    {
      EXPECT_TRUE(test::bitwiseEqual(given->positions(), reordered->positions()));
      EXPECT_TRUE(test::bitwiseEqual(given->velocities(), reordered->velocities()));
    }
    else
    {
      // The coloring follows the constraint graph's numbering: another order, same physics.
      EXPECT_LT(test::maxDistance(given->positions(), reordered->positions()), 1e-3);
    }
    EXPECT_TRUE(test::bitwiseEqual(reordered->restPositions(), body.mesh.points));
    EXPECT_EQ(reordered->inverseMasses(), given->inverseMasses());
  }
}

TEST(Reorder, PbdTetBodiesInInputOrderMatchTheRunAsGiven)
{
  const TetMesh mesh = shuffledBox(5);
  Body body;
  body.mesh.points = mesh.points;
  body.mesh.tets = mesh.tets;
  body.material.physical.density = 1000.0;
  for (PbdSolver solver : { PbdSolver::GaussSeidel, PbdSolver::Jacobi, PbdSolver::ParallelGaussSeidel })
  {
    PbdSettings settings;
    settings.solver = solver;
    settings.floorEnabled = true;
    settings.floor.origin = Vec3(0, 0, 0.049);
    settings.iterations = solver == PbdSolver::Jacobi ? 10 : 100; // near convergence
    std::unique_ptr<Simulation> given = makePbdSimulation(body, settings, VertexOrdering::Input);
    PbdSimulation* inner = nullptr;
    std::unique_ptr<Simulation> reordered = makePbdSimulation(body, settings, VertexOrdering::Morton, &inner);
    given->advance(0.3);
    reordered->advance(0.3);
    // Gauss-Seidel visits the constraints in another order (the renumbered edges and tets are
    // sorted by their vertices), so the iterates differ by what the iterations leave unsolved
    // (run near convergence here; measured 2.6e-5 m for Gauss-Seidel, 5.8e-5 m for the colored
    // solver, on a 5 cm box); Jacobi only sums in another order (1.4e-16 m).
    const double tolerance = solver == PbdSolver::Jacobi ? 1e-12 : 1e-4;
    EXPECT_LT(test::maxDistance(given->positions(), reordered->positions()), tolerance)
      << static_cast<int>(solver);
    const std::vector<double> a = given->tetVolumeRatios(), b = reordered->tetVolumeRatios();
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t t = 0; t < a.size(); ++t)
    {
      ASSERT_NEAR(a[t], b[t], 100 * tolerance) << "tet " << t;
    }
    // Tets keep their input indices in the solver inside.
    EXPECT_EQ(inner->volumes().size(), mesh.tets.size());
    EXPECT_FALSE(inner->tetBroken(0));
  }
}

TEST(Reorder, PbdReorderedRunIsTheSameAtAnyThreadCount)
{
  const TetMesh mesh = shuffledBox(8);
  Body body;
  body.mesh.points = mesh.points;
  body.mesh.tets = mesh.tets;
  for (PbdSolver solver : { PbdSolver::Jacobi, PbdSolver::ParallelGaussSeidel })
  {
    std::vector<std::vector<Vec3>> results;
    for (int threads : { 1, 2, 3 })
    {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
      PbdSettings settings;
      settings.solver = solver;
      settings.floorEnabled = true;
      settings.floor.origin = Vec3(0, 0, 0.049);
      std::unique_ptr<Simulation> sim = makePbdSimulation(body, settings);
      sim->advance(0.1);
      results.push_back(sim->positions());
    }
    EXPECT_TRUE(test::bitwiseEqual(results[0], results[1])) << static_cast<int>(solver);
    EXPECT_TRUE(test::bitwiseEqual(results[0], results[2])) << static_cast<int>(solver);
  }
}
