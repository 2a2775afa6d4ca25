// The broad phases are exact accelerations: each query structure finds exactly the pairs within
// reach (each once), and the detector returns the brute-force contact set, bit for bit, with
// every broad phase, on random scenes (uniform and clustered, particles of several radii, tet
// bodies, fast points, static and moving obstacles), at 1 and 2 threads.
#include "collision_test_scenes.h"
#include "softbody/mesh/mesh_generators.h"
#include "test_support.h"

#include <tbb/global_control.h>

#include <gtest/gtest.h>

#include <random>

using namespace softbody;
using namespace softbody::test;

namespace
{

/// Random points: uniform in a cube of side `size`, or in a few tight clusters.
std::vector<Vec3> randomPoints(std::size_t count, double size, bool clustered, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.5 * size, 0.5 * size);
  std::normal_distribution<double> spread(0.0, 0.03 * size);
  std::vector<Vec3> centres;
  for (int c = 0; c < 4; ++c)
  {
    centres.emplace_back(u(rng), u(rng), u(rng));
  }
  std::vector<Vec3> points;
  for (std::size_t i = 0; i < count; ++i)
  {
    if (clustered)
    {
      points.push_back(centres[i % centres.size()] + Vec3(spread(rng), spread(rng), spread(rng)));
    }
    else
    {
      points.emplace_back(u(rng), u(rng), u(rng));
    }
  }
  return points;
}

std::vector<double> randomReaches(std::size_t count, double largest, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, largest);
  std::vector<double> reaches(count);
  for (double& r : reaches)
  {
    r = u(rng);
  }
  return reaches;
}

/// The pairs (i, j), i < j, found by a structure's queries, sorted; and the true ones.
template <typename Query>
std::vector<std::pair<int, int>> pairsFound(std::size_t n, const Query& query)
{
  std::vector<std::pair<int, int>> pairs;
  for (std::size_t i = 0; i < n; ++i)
  {
    query(i, [&](std::int32_t j) {
      if (static_cast<std::size_t>(j) > i)
      {
        pairs.emplace_back(static_cast<int>(i), j);
      }
    });
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

/// The grid's pairs from its half stencil (each must come exactly once: no dedup here), with
/// the exact distance test the detector's narrow phase applies.
std::vector<std::pair<int, int>> gridPairs(const UniformGrid& grid, const std::vector<Vec3>& x,
  const std::vector<double>& reach)
{
  std::vector<std::pair<int, int>> pairs;
  for (std::size_t s = 0; s < grid.entryCount(); ++s)
  {
    grid.forEachPairFrom(s, [&](std::int32_t a, std::int32_t b) {
      EXPECT_LT(a, b);
      const double within = reach[static_cast<std::size_t>(a)] + reach[static_cast<std::size_t>(b)];
      if ((x[static_cast<std::size_t>(a)] - x[static_cast<std::size_t>(b)]).squaredNorm() <= within * within)
      {
        pairs.emplace_back(a, b);
      }
    });
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

std::vector<std::pair<int, int>> truePairs(const std::vector<Vec3>& x, const std::vector<double>& reach)
{
  std::vector<std::pair<int, int>> pairs;
  for (std::size_t i = 0; i < x.size(); ++i)
  {
    for (std::size_t j = i + 1; j < x.size(); ++j)
    {
      const double within = reach[i] + reach[j];
      if ((x[i] - x[j]).squaredNorm() <= within * within)
      {
        pairs.emplace_back(static_cast<int>(i), static_cast<int>(j));
      }
    }
  }
  return pairs;
}

/// A mixed random scene: tet bodies (jittered boxes), particle bodies of two radii, moved
/// from `start` to `predicted` by small noise plus a few fast points.
struct PointScene
{
  CollisionGeometry geometry;
  std::vector<Vec3> start, predicted;
  std::vector<ObstacleSurface> obstacles;
};

PointScene randomScene(unsigned seed, std::size_t particles, bool clustered, double radius)
{
  PointScene scene;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  addTetBody(scene.geometry, makeTetBox(4, 3, 2, 0.05, Vec3(u(rng), u(rng), u(rng))), 0);
  addTetBody(scene.geometry, makeTetBox(3, 3, 3, 0.04, Vec3(u(rng), u(rng), u(rng))), 1);
  const std::vector<Vec3> centres = randomPoints(particles, 0.6, clustered, seed + 1);
  // Bodies of 25 particles, alternately of radius r and 2 r.
  for (std::size_t first = 0; first < centres.size(); first += 25)
  {
    const std::size_t last = std::min(centres.size(), first + 25);
    const auto body = static_cast<std::int32_t>(2 + first / 25);
    addParticleBody(scene.geometry, { centres.begin() + static_cast<std::ptrdiff_t>(first),
      centres.begin() + static_cast<std::ptrdiff_t>(last) }, (body % 2 ? 2.0 : 1.0) * radius, body);
  }
  scene.start = jitter(scene.geometry.rest, 0.02, seed + 2);
  scene.predicted = jitter(scene.start, 0.005, seed + 3);
  for (std::size_t i = 0; i < scene.predicted.size(); i += 97)
  {
    scene.predicted[i] += Vec3(0.0, 0.0, -0.3); // fast: 0.3 m in one substep
  }
  scene.obstacles.push_back(boxObstacle(Vec3(-0.1, -0.1, -0.1), Vec3(0.05, 0.1, 0.0)));
  ObstacleSurface moving = flatObstacle(-0.15, 0.4);
  for (const Vec3& v : moving.vertices)
  {
    moving.velocities.push_back(Vec3(0.5 * v.y(), 0.0, 2.0));
  }
  scene.obstacles.push_back(moving);
  return scene;
}

ContactSet detectWith(const PointScene& scene, BroadPhase kind, CollisionMode mode, double margin,
  std::size_t threads, BroadPhase* used = nullptr)
{
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  CollisionSettings settings;
  settings.mode = mode;
  settings.broadPhase = kind;
  settings.margin = margin;
  FloorPlane floor;
  floor.origin = Vec3(0, 0, -0.25);
  CollisionDetector detector(scene.geometry, settings, true, floor);
  detector.setObstacles(scene.obstacles, 0.1);
  ContactSet contacts;
  // Twice: the second detection refits the trees built by the first.
  detector.detect(scene.geometry.rest, scene.start, 0.08, 0.01, contacts);
  detector.detect(scene.start, scene.predicted, 0.09, 0.01, contacts);
  if (used)
  {
    *used = detector.stats().broadPhase;
  }
  return contacts;
}

} // namespace

TEST(BroadPhaseStructures, FindExactlyThePairsWithinReachEachOnce)
{
  for (unsigned seed = 1; seed <= 4; ++seed)
  {
    for (bool clustered : { false, true })
    {
      const std::vector<Vec3> x = randomPoints(1500, 1.0, clustered, seed);
      // Mostly small reaches, a few large ones (a fast point).
      std::vector<double> reach = randomReaches(x.size(), 0.02, seed + 10);
      reach[seed] = 0.2;
      const auto expected = truePairs(x, reach);
      ASSERT_GT(expected.size(), 50u);

      UniformGrid grid;
      grid.build(x, reach, 2.0 * *std::max_element(reach.begin(), reach.end()));
      EXPECT_TRUE(grid.dense());
      EXPECT_EQ(gridPairs(grid, x, reach), expected);
      EXPECT_EQ(pairsFound(x.size(), [&](std::size_t i, auto visit) {
        grid.forEachNear(x[i], reach[i], -1, [&](std::int32_t j) {
          const double within = reach[i] + reach[static_cast<std::size_t>(j)];
          if ((x[i] - x[static_cast<std::size_t>(j)]).squaredNorm() <= within * within)
          {
            visit(j);
          }
        });
      }), expected);
      PointOctree octree;
      octree.build(x, reach);
      EXPECT_EQ(pairsFound(x.size(), [&](std::size_t i, auto visit) { octree.forEachNear(x[i], reach[i], static_cast<std::int32_t>(i), visit); }), expected);
      // The BVH over point boxes (degenerate triangles): boxes within radius = sum of reaches.
      std::vector<Aabb> boxes(x.size());
      for (std::size_t i = 0; i < x.size(); ++i)
      {
        boxes[i].grow(x[i]);
        boxes[i].inflate(reach[i]);
      }
      TriangleBvh bvh;
      bvh.build(boxes);
      // Boxes are looser than spheres: keep the exact test as the detector's narrow phase does.
      auto bvhPairs = pairsFound(x.size(), [&](std::size_t i, auto visit) {
        bvh.forEachNear(x[i], reach[i], [&](std::int32_t j) {
          const double within = reach[i] + reach[static_cast<std::size_t>(j)];
          if ((x[i] - x[static_cast<std::size_t>(j)]).squaredNorm() <= within * within)
          {
            visit(j);
          }
        });
      });
      EXPECT_EQ(bvhPairs, expected);
      // Refit after a move: the same answer as a fresh build.
      const std::vector<Vec3> moved = jitter(x, 0.05, seed + 20);
      for (std::size_t i = 0; i < x.size(); ++i)
      {
        boxes[i] = Aabb{};
        boxes[i].grow(moved[i]);
        boxes[i].inflate(reach[i]);
      }
      bvh.refit(boxes);
      auto refitPairs = pairsFound(x.size(), [&](std::size_t i, auto visit) {
        bvh.forEachNear(moved[i], reach[i], [&](std::int32_t j) {
          const double within = reach[i] + reach[static_cast<std::size_t>(j)];
          if ((moved[i] - moved[static_cast<std::size_t>(j)]).squaredNorm() <= within * within)
          {
            visit(j);
          }
        });
      });
      EXPECT_EQ(refitPairs, truePairs(moved, reach));
    }
  }
}

TEST(BroadPhaseStructures, HashedGridForSparsePointsFindsThePairsToo)
{
  // Clusters a kilometre apart: the dense cell box would be far too large, so the grid hashes.
  std::vector<Vec3> x = randomPoints(800, 0.5, true, 5);
  for (std::size_t i = 0; i < x.size(); i += 2)
  {
    x[i] += Vec3(1000.0, -2000.0, 500.0);
  }
  const std::vector<double> reach = randomReaches(x.size(), 0.01, 6);
  UniformGrid grid;
  grid.build(x, reach, 0.02);
  EXPECT_FALSE(grid.dense());
  const auto expected = truePairs(x, reach);
  ASSERT_GT(expected.size(), 50u);
  EXPECT_EQ(gridPairs(grid, x, reach), expected);
  EXPECT_EQ(pairsFound(x.size(), [&](std::size_t i, auto visit) {
    grid.forEachNear(x[i], reach[i], static_cast<std::int32_t>(i), [&](std::int32_t j) {
      const double within = reach[i] + reach[static_cast<std::size_t>(j)];
      if ((x[i] - x[static_cast<std::size_t>(j)]).squaredNorm() <= within * within)
      {
        visit(j);
      }
    });
  }), expected);
  // Reaches as large as the clusters: many points per cell and per bucket, each pair once.
  std::vector<Vec3> few(x.begin(), x.begin() + 40);
  std::vector<double> fewReach(reach.begin(), reach.begin() + 40);
  for (double& r : fewReach)
  {
    r = 0.3;
  }
  grid.build(few, fewReach, 0.6);
  EXPECT_EQ(pairsFound(few.size(), [&](std::size_t i, auto visit) {
    grid.forEachNear(few[i], fewReach[i], -1, [&](std::int32_t j) {
      if ((few[i] - few[static_cast<std::size_t>(j)]).norm() <= 0.6)
      {
        visit(j);
      }
    });
  }), truePairs(few, fewReach));
  EXPECT_EQ(gridPairs(grid, few, fewReach), truePairs(few, fewReach));
}

TEST(BroadPhaseStructures, GridWithGroupsSkipsExactlyThePairsOfOneGroup)
{
  // The detector's bodies as groups (no self collision): the grid reports every pair within
  // reach of two different groups and none of one group, in the dense and the hashed layout.
  for (bool sparse : { false, true })
  {
    std::vector<Vec3> x = randomPoints(1200, 0.5, true, 7);
    if (sparse)
    {
      for (std::size_t i = 0; i < x.size(); i += 2)
      {
        x[i] += Vec3(1000.0, -2000.0, 500.0);
      }
    }
    const std::vector<double> reach = randomReaches(x.size(), 0.02, 8);
    std::vector<std::int32_t> groups(x.size());
    for (std::size_t i = 0; i < x.size(); ++i)
    {
      groups[i] = static_cast<std::int32_t>((i * 7) % 5); // interleaved, as bodies sorted by index are not
    }
    std::vector<std::pair<int, int>> expected;
    for (const auto& [a, b] : truePairs(x, reach))
    {
      if (groups[static_cast<std::size_t>(a)] != groups[static_cast<std::size_t>(b)])
      {
        expected.emplace_back(a, b);
      }
    }
    ASSERT_GT(expected.size(), 50u);
    ASSERT_LT(expected.size(), truePairs(x, reach).size()); // some pairs are within a group
    UniformGrid grid;
    grid.build(x, reach, 2.0 * *std::max_element(reach.begin(), reach.end()), groups);
    EXPECT_EQ(grid.dense(), !sparse);
    EXPECT_EQ(gridPairs(grid, x, reach), expected);
  }
}

TEST(BroadPhaseStructures, SinglePrecisionFilterKeepsPairsAtTheirReachFarFromTheOrigin)
{
  // The grid filters in single precision: a mesh far from the origin or in millimetres must
  // lose no pair at exactly its reach. Lattices of points whose neighbours are within reach
  // only by rounding (spacing = the sum of two reaches), far away and tiny, jittered and grouped.
  struct Case
  {
    Vec3 offset;
    double spacing;
  };
  for (const Case& c : { Case{ Vec3(1e6, -2e6, 3e5), 0.01 }, Case{ Vec3(0.0, 0.0, 0.0), 1e-6 },
         Case{ Vec3(-4e3, 7e3, 1e4), 1e-3 }, Case{ Vec3(250.0, 250.0, 250.0), 0.5 } })
  {
    std::vector<Vec3> x;
    std::vector<std::int32_t> groups;
    std::mt19937 rng(3);
    std::uniform_int_distribution<int> ulps(-2, 2);
    for (int k = 0; k < 12; ++k)
    {
      for (int j = 0; j < 12; ++j)
      {
        for (int i = 0; i < 12; ++i)
        {
          Vec3 p = c.offset + c.spacing * Vec3(i, j, k);
          for (int a = 0; a < 3; ++a) // a few ulps either way: on both sides of the reach
          {
            for (int u = ulps(rng); u != 0; u += u > 0 ? -1 : 1)
            {
              p[a] = std::nextafter(p[a], u > 0 ? 1e300 : -1e300);
            }
          }
          x.push_back(p);
          groups.push_back((i / 3 + j / 3 + k / 3) % 2);
        }
      }
    }
    const std::vector<double> reach(x.size(), 0.5 * c.spacing);
    std::vector<std::pair<int, int>> expected;
    for (const auto& [a, b] : truePairs(x, reach))
    {
      if (groups[static_cast<std::size_t>(a)] != groups[static_cast<std::size_t>(b)])
      {
        expected.emplace_back(a, b);
      }
    }
    ASSERT_GT(expected.size(), 100u) << "offset " << c.offset.transpose() << ", spacing " << c.spacing;
    UniformGrid grid;
    grid.build(x, reach, c.spacing, groups);
    EXPECT_EQ(gridPairs(grid, x, reach), expected) << "offset " << c.offset.transpose() << ", spacing " << c.spacing;
  }
}

TEST(BroadPhaseStructures, GridRefusesGroupsThatDoNotMatchThePoints)
{
  UniformGrid grid;
  const std::vector<Vec3> x = randomPoints(10, 1.0, false, 1);
  const std::vector<double> reach(x.size(), 0.1);
  EXPECT_THROW(grid.build(x, reach, 0.2, std::vector<std::int32_t>(9, 0)), std::invalid_argument);
  std::vector<std::int32_t> groups(x.size(), 0);
  groups[4] = std::numeric_limits<std::int32_t>::min();
  EXPECT_THROW(grid.build(x, reach, 0.2, groups), std::invalid_argument);
}

TEST(BroadPhases, SameContactSetAsBruteForceOnRandomScenes)
{
  std::size_t scenes = 0;
  for (unsigned seed = 1; seed <= 3; ++seed)
  {
    for (bool clustered : { false, true })
    {
      for (double radius : { 0.004, 0.012 })
      {
        const PointScene scene = randomScene(seed, 400, clustered, radius);
        for (CollisionMode mode : { CollisionMode::Obstacles, CollisionMode::ObstaclesAndBodies,
               CollisionMode::ObstaclesBodiesAndSelf })
        {
          const ContactSet reference = detectWith(scene, BroadPhase::BruteForce, mode, 0.0, 2);
          if (mode != CollisionMode::Obstacles)
          {
            EXPECT_GT(reference.size(), 20u) << "seed " << seed;
          }
          for (BroadPhase kind : { BroadPhase::UniformGrid, BroadPhase::Octree, BroadPhase::Automatic })
          {
            const ContactSet contacts = detectWith(scene, kind, mode, 0.0, 2);
            EXPECT_TRUE(sameContacts(contacts, reference))
              << "broad phase " << static_cast<int>(kind) << ", mode " << static_cast<int>(mode) << ", seed "
              << seed << (clustered ? " clustered" : " uniform") << ", radius " << radius << ": "
              << contacts.size() << " contacts against " << reference.size();
          }
          ++scenes;
        }
      }
    }
  }
  EXPECT_EQ(scenes, 36u);
}

TEST(BroadPhases, BitIdenticalContactsAtOneAndTwoThreads)
{
  const PointScene scene = randomScene(9, 3000, true, 0.006);
  for (BroadPhase kind : { BroadPhase::BruteForce, BroadPhase::UniformGrid, BroadPhase::Octree })
  {
    const ContactSet one = detectWith(scene, kind, CollisionMode::ObstaclesBodiesAndSelf, 0.0, 1);
    const ContactSet two = detectWith(scene, kind, CollisionMode::ObstaclesBodiesAndSelf, 0.0, 2);
    EXPECT_GT(one.size(), 100u);
    EXPECT_TRUE(sameContacts(one, two)) << "broad phase " << static_cast<int>(kind);
  }
}

TEST(BroadPhases, AutomaticPicksBruteForceForTinyScenesAndTheGridForLargeOnes)
{
  BroadPhase used = BroadPhase::Automatic;
  PointScene tiny;
  addParticleBody(tiny.geometry, randomPoints(20, 0.1, false, 3), 0.01, 0);
  tiny.start = tiny.predicted = tiny.geometry.rest;
  detectWith(tiny, BroadPhase::Automatic, CollisionMode::ObstaclesAndBodies, 0.0, 1, &used);
  EXPECT_EQ(used, BroadPhase::BruteForce);
  const PointScene large = randomScene(4, 3000, false, 0.004);
  detectWith(large, BroadPhase::Automatic, CollisionMode::ObstaclesAndBodies, 0.0, 1, &used);
  EXPECT_EQ(used, BroadPhase::UniformGrid);
}
