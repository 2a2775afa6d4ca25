// Render corrections of a skinned surface against obstacles (skin_correction.h): vertices the
// skin puts inside an obstacle go onto its surface, nothing else moves.
#include "softbody/common/errors.h"
#include "softbody/lattice/lattice.h"
#include "softbody/lattice/skin_correction.h"
#include "softbody/lattice/skinning.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>

namespace softbody
{
namespace
{
/// The closed box [lo, hi] as 12 triangles with outward normals.
ObstacleSurface boxObstacle(const Vec3& lo, const Vec3& hi)
{
  ObstacleSurface box;
  for (int c = 0; c < 8; ++c)
  {
    box.vertices.emplace_back((c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(), (c & 4) ? hi.z() : lo.z());
  }
  // Each face as a quad (a, b, c, d) counter-clockwise seen from outside.
  const int quads[6][4] = { { 0, 2, 3, 1 }, { 4, 5, 7, 6 }, { 0, 1, 5, 4 }, { 2, 6, 7, 3 }, { 0, 4, 6, 2 },
    { 1, 3, 7, 5 } };
  for (const auto& q : quads)
  {
    box.triangles.push_back({ q[0], q[1], q[2] });
    box.triangles.push_back({ q[0], q[2], q[3] });
  }
  return box;
}

/// Signed distance to the box's surface, negative inside.
double boxDistance(const Vec3& p, const Vec3& lo, const Vec3& hi)
{
  const Vec3 centre = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  const Vec3 q = (p - centre).cwiseAbs() - half;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}
} // namespace

TEST(SkinCorrection, TheBoxHasOutwardNormals)
{
  const ObstacleSurface box = boxObstacle(Vec3::Zero(), Vec3::Ones());
  for (const auto& t : box.triangles)
  {
    const Vec3 a = box.vertices[t[0]], b = box.vertices[t[1]], c = box.vertices[t[2]];
    EXPECT_GT((b - a).cross(c - a).dot((a + b + c) / 3.0 - Vec3::Constant(0.5)), 0.0);
  }
}

TEST(SkinCorrection, VerticesInsideWithinReachGoOntoTheNearestFace)
{
  const Vec3 lo(0, 0, 0), hi(1, 1, 1);
  const std::vector<ObstacleSurface> obstacles{ boxObstacle(lo, hi) };
  std::vector<Vec3> vertices = test::randomVectors(4000, 1.5, 5);
  for (Vec3& v : vertices)
  {
    v += Vec3::Constant(0.5);
  }
  const std::vector<Vec3> before = vertices;
  const double reach = 0.2;
  const SkinCorrection done = keepOutsideObstacles(obstacles, std::vector<double>(vertices.size(), reach), vertices);
  std::size_t inside = 0;
  double deepest = 0.0;
  for (std::size_t v = 0; v < vertices.size(); ++v)
  {
    const double d = boxDistance(before[v], lo, hi);
    if (d < 0.0 && -d <= reach)
    {
      // Onto the surface, moved by its depth along one axis (the nearest face's normal).
      ++inside;
      deepest = std::max(deepest, -d);
      EXPECT_NEAR(boxDistance(vertices[v], lo, hi), 0.0, 1e-12) << before[v].transpose();
      EXPECT_NEAR((vertices[v] - before[v]).norm(), -d, 1e-12);
      EXPECT_EQ(((vertices[v] - before[v]).array().abs() > 1e-12).count(), 1) << "along one axis";
    }
    else
    {
      EXPECT_EQ(vertices[v], before[v]) << "outside, or deeper than the reach: untouched";
    }
  }
  ASSERT_GT(inside, 50u);
  EXPECT_EQ(done.moved, inside);
  EXPECT_DOUBLE_EQ(done.deepest, deepest);
}

TEST(SkinCorrection, AnOpenRampPushesAlongItsNormalOnly)
{
  // A ramp through the origin, tilted 30 degrees about x, free side up; a second copy of it
  // facing down (reversed triangles) pushes the same vertices the other way.
  const double s = std::sin(M_PI / 6), c = std::cos(M_PI / 6);
  ObstacleSurface ramp;
  ramp.vertices = { { -2, -2 * c, -2 * s }, { 2, -2 * c, -2 * s }, { 2, 2 * c, 2 * s }, { -2, 2 * c, 2 * s } };
  ramp.triangles = { { 0, 1, 2 }, { 0, 2, 3 } };
  const Vec3 n(0, -s, c);
  const auto onRamp = [&](double x, double along) { return Vec3(x, along * c, along * s); };
  std::vector<Vec3> vertices = { onRamp(0.3, 0.1) - 0.05 * n, onRamp(0.1, 0.2) + 0.05 * n,
    onRamp(0, 0) - 0.5 * n };
  const std::vector<Vec3> before = vertices;
  const SkinCorrection done = keepOutsideObstacles({ ramp }, { 0.1, 0.1, 0.1 }, vertices);
  EXPECT_EQ(done.moved, 1u);
  EXPECT_NEAR(done.deepest, 0.05, 1e-12);
  EXPECT_LT((vertices[0] - (before[0] + 0.05 * n)).norm(), 1e-12);
  EXPECT_EQ(vertices[1], before[1]); // on the free side
  EXPECT_EQ(vertices[2], before[2]); // 0.5 m behind: beyond its reach, the other side of a wall

  std::swap(ramp.triangles[0][1], ramp.triangles[0][2]);
  std::swap(ramp.triangles[1][1], ramp.triangles[1][2]);
  vertices = before;
  EXPECT_EQ(keepOutsideObstacles({ ramp }, { 0.1, 0.1, 0.1 }, vertices).moved, 1u);
  EXPECT_LT((vertices[1] - (before[1] - 0.05 * n)).norm(), 1e-12);
}

TEST(SkinCorrection, AVoxelizedBodyRestingOnABoxIsDrawnOutsideIt)
{
  // A voxelized ball whose particles rest on the top of a box (lowest particle layer on it),
  // squashed 30 % vertically as a contact does: its surface, bound by extrapolation below the
  // bottom layer, is skinned into the box until corrected, by at most its reach.
  LatticeGrid grid;
  grid.origin = Vec3::Constant(-0.6);
  grid.spacing = 0.1;
  grid.nodes = { 13, 13, 13 };
  std::vector<char> flags(grid.nodeCount());
  for (int k = 0; k < 13; ++k)
    for (int j = 0; j < 13; ++j)
      for (int i = 0; i < 13; ++i)
        flags[grid.nodeIndex(i, j, k)] = grid.position(i, j, k).norm() < 0.5;
  const Lattice lattice = buildLattice(grid, flags);
  std::vector<Vec3> surface = test::randomVectors(2000, 1.0, 9);
  for (Vec3& v : surface)
  {
    v = 0.55 * v.normalized();
  }
  const Skin skin = bindToLattice(lattice, surface);
  double bottom = 1e9;
  for (const Vec3& p : lattice.points)
  {
    bottom = std::min(bottom, p.z());
  }
  std::vector<Vec3> particles = lattice.points;
  for (Vec3& p : particles)
  {
    p.z() = 0.7 * (p.z() - bottom); // squashed onto z = 0, the box's top
  }
  const Vec3 lo(-1, -1, -1), hi(1, 1, 0);
  std::vector<Vec3> skinned;
  applySkin(skin, particles, skinned);
  const std::vector<Vec3> before = skinned;
  const std::vector<double> reach = skinReach(skin, particles, skinned);
  double deepestBefore = 0.0;
  for (const Vec3& v : before)
  {
    deepestBefore = std::max(deepestBefore, -boxDistance(v, lo, hi));
  }
  ASSERT_GT(deepestBefore, 0.02) << "the skin alone puts the surface inside the box";

  std::vector<Vec3> oneThread = skinned;
  SkinCorrection done;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    done = keepOutsideObstacles({ boxObstacle(lo, hi) }, reach, oneThread);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    keepOutsideObstacles({ boxObstacle(lo, hi) }, reach, skinned);
  }
  EXPECT_EQ(skinned, oneThread) << "the same at any thread count";
  EXPECT_GT(done.moved, 0u);
  EXPECT_NEAR(done.deepest, deepestBefore, 1e-12);
  for (std::size_t v = 0; v < skinned.size(); ++v)
  {
    EXPECT_GE(boxDistance(skinned[v], lo, hi), -1e-12);
    EXPECT_LE(-boxDistance(before[v], lo, hi), reach[v]) << "every inside vertex was within reach";
  }
}

TEST(SkinCorrection, RefusesTrianglesIndexingMissingVertices)
{
  ObstacleSurface bad;
  bad.vertices = { Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY() };
  bad.triangles = { { 0, 1, 7 } };
  std::vector<Vec3> vertices{ Vec3::Zero() };
  try
  {
    keepOutsideObstacles({ bad }, { 1.0 }, vertices);
    FAIL() << "no error";
  }
  catch (const InvalidInputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("vertex index 7"), std::string::npos) << e.what();
  }
}

} // namespace softbody
