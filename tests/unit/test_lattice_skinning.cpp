// Particle lattices (voxelized bodies) and skinning a surface onto a body.
#include "softbody/common/errors.h"
#include "softbody/lattice/lattice.h"
#include "softbody/mesh/mesh_generators.h"
#include "softbody/lattice/skin_correction.h"
#include "softbody/lattice/skinning.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>

namespace softbody
{
namespace
{
Lattice latticeOf(const LatticeGrid& grid, const std::function<bool(const Vec3&)>& inside)
{
  std::vector<char> flags(grid.nodeCount());
  for (int k = 0; k < grid.nodes[2]; ++k)
    for (int j = 0; j < grid.nodes[1]; ++j)
      for (int i = 0; i < grid.nodes[0]; ++i)
        flags[grid.nodeIndex(i, j, k)] = inside(grid.position(i, j, k));
  return buildLattice(grid, flags);
}

LatticeGrid gridAround(double halfWidth, double spacing)
{
  LatticeGrid grid;
  const int n = static_cast<int>(std::ceil(2 * halfWidth / spacing)) + 1;
  grid.origin = Vec3::Constant(-halfWidth);
  grid.spacing = spacing;
  grid.nodes = { n, n, n };
  return grid;
}

TEST(Lattice, FullBoxHasTheAnalyticLinkCounts)
{
  const int n = 5;
  LatticeGrid grid;
  grid.nodes = { n, n, n };
  grid.spacing = 0.1;
  const Lattice lattice = buildLattice(grid, std::vector<char>(grid.nodeCount(), 1));
  ASSERT_EQ(lattice.points.size(), std::size_t(n * n * n));
  std::array<std::size_t, 3> kinds{};
  std::vector<int> degree(lattice.points.size(), 0);
  for (std::size_t l = 0; l < lattice.links.size(); ++l)
  {
    ++kinds[static_cast<std::size_t>(lattice.linkKinds[l])];
    ++degree[std::size_t(lattice.links[l][0])];
    ++degree[std::size_t(lattice.links[l][1])];
    const double length = (lattice.points[std::size_t(lattice.links[l][0])] - lattice.points[std::size_t(lattice.links[l][1])]).norm();
    EXPECT_NEAR(length, 0.1 * std::sqrt(double(int(lattice.linkKinds[l]) + 1)), 1e-12);
  }
  EXPECT_EQ(kinds[0], std::size_t(3 * n * n * (n - 1)));           // axis
  EXPECT_EQ(kinds[1], std::size_t(6 * n * (n - 1) * (n - 1)));     // face diagonals
  EXPECT_EQ(kinds[2], std::size_t(4 * (n - 1) * (n - 1) * (n - 1))); // body diagonals
  // Interior particles see all 26 neighbors, corners 7.
  EXPECT_EQ(degree[grid.nodeIndex(2, 2, 2)], 26);
  EXPECT_EQ(degree[grid.nodeIndex(0, 0, 0)], 7);
  EXPECT_EQ(degree[grid.nodeIndex(2, 0, 0)], 11);
}

TEST(Lattice, FullCellsSplitIntoConformingPositiveKuhnTets)
{
  const double r = 0.5, h = 0.1;
  const Lattice lattice = latticeOf(gridAround(0.6, h), [&](const Vec3& p) { return p.norm() < r; });
  const std::vector<Tet> tets = latticeTets(lattice);
  ASSERT_FALSE(tets.empty());
  EXPECT_EQ(tets.size() % 6, 0u);
  double volume = 0.0;
  for (const Tet& t : tets)
  {
    const double v = signedTetVolume(lattice.points[std::size_t(t[0])], lattice.points[std::size_t(t[1])],
      lattice.points[std::size_t(t[2])], lattice.points[std::size_t(t[3])]);
    EXPECT_NEAR(v, h * h * h / 6.0, 1e-15);
    volume += v;
  }
  EXPECT_NEAR(volume, double(tets.size() / 6) * h * h * h, 1e-12);
  // Conforming: every face is shared by at most two tets, and interior faces by exactly two.
  std::map<std::array<std::int32_t, 3>, int> faces;
  for (const Tet& t : tets)
  {
    for (int skip = 0; skip < 4; ++skip)
    {
      std::array<std::int32_t, 3> f{};
      for (int c = 0, n = 0; c < 4; ++c)
      {
        if (c != skip)
        {
          f[std::size_t(n++)] = t[std::size_t(c)];
        }
      }
      std::sort(f.begin(), f.end());
      ++faces[f];
    }
  }
  for (const auto& [face, count] : faces)
  {
    EXPECT_LE(count, 2);
  }
  TetMesh mesh{ lattice.points, tets };
  const TetMeshReport report = inspectTetMesh(mesh);
  EXPECT_EQ(report.invertedTets, 0u);
  EXPECT_EQ(report.degenerateTets, 0u);
}

TEST(Lattice, VoxelizedSphereHasTheExpectedParticleCount)
{
  const double r = 1.0, h = 0.05;
  const Lattice lattice = latticeOf(gridAround(1.1, h), [&](const Vec3& p) { return p.norm() < r; });
  const double expected = 4.0 / 3.0 * M_PI * r * r * r / (h * h * h);
  EXPECT_NEAR(double(lattice.points.size()) / expected, 1.0, 0.02);
}

TEST(Skinning, UndeformedLatticeReproducesTheSurfaceExactly)
{
  const double r = 0.5;
  const Lattice lattice = latticeOf(gridAround(0.6, 0.1), [&](const Vec3& p) { return p.norm() < r; });
  // Surface vertices on the sphere: all outside the lattice's full cells, bound by extrapolation.
  std::vector<Vec3> surface = test::randomVectors(200, 1.0, 3);
  for (Vec3& v : surface)
  {
    v = r * v.normalized();
  }
  const Skin skin = bindToLattice(lattice, surface);
  EXPECT_GT(skin.outsideCount, 0u);
  std::vector<Vec3> skinned;
  applySkin(skin, lattice.points, skinned);
  for (std::size_t v = 0; v < surface.size(); ++v)
  {
    EXPECT_LT((skinned[v] - surface[v]).norm(), 1e-12);
  }
}

TEST(Skinning, SurfaceBelowTheFloorIsMovedOntoIt)
{
  // A body resting on the floor z = 0 (its lowest particles on it): surface vertices bound by
  // extrapolation below its bottom layer come out below the floor until corrected.
  const Lattice lattice = latticeOf(gridAround(0.6, 0.1), [&](const Vec3& p) { return p.norm() < 0.5; });
  double bottom = 1e9;
  for (const Vec3& p : lattice.points)
  {
    bottom = std::min(bottom, p.z());
  }
  std::vector<Vec3> surface = test::randomVectors(200, 1.0, 3);
  for (Vec3& v : surface)
  {
    v = 0.55 * v.normalized();
  }
  const Skin skin = bindToLattice(lattice, surface);
  std::vector<Vec3> particles = lattice.points;
  for (Vec3& p : particles)
  {
    p.z() -= bottom; // rests on z = 0
  }
  std::vector<Vec3> skinned;
  applySkin(skin, particles, skinned);
  const auto lowest = [&] {
    double z = 1e9;
    for (const Vec3& v : skinned)
    {
      z = std::min(z, v.z());
    }
    return z;
  };
  ASSERT_LT(lowest(), -0.01);
  const std::vector<Vec3> before = skinned;
  FloorPlane floor;
  const std::size_t moved = keepAboveFloor(floor, skinned).moved;
  EXPECT_GT(moved, 0u);
  EXPECT_EQ(lowest(), 0.0);
  std::size_t changed = 0;
  for (std::size_t v = 0; v < skinned.size(); ++v)
  {
    changed += skinned[v] != before[v] ? 1 : 0;
    if (before[v].z() >= 0.0)
    {
      EXPECT_EQ(skinned[v], before[v]); // above the floor: untouched
    }
    else
    {
      EXPECT_EQ(skinned[v].head<2>(), before[v].head<2>()); // moved along the normal only
    }
  }
  EXPECT_EQ(changed, moved);
}

TEST(Skinning, RigidMotionOfTheBodyMovesTheSurfaceRigidly)
{
  const double r = 0.5;
  const Lattice lattice = latticeOf(gridAround(0.6, 0.1), [&](const Vec3& p) { return p.norm() < r; });
  std::vector<Vec3> surface = test::randomVectors(100, 1.0, 5);
  for (Vec3& v : surface)
  {
    v = r * v.normalized();
  }
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Vec3 shift(0.3, -1.0, 2.0);
  std::vector<Vec3> moved = lattice.points;
  for (Vec3& p : moved)
  {
    p = rotation * p + shift;
  }
  const Skin skin = bindToLattice(lattice, surface);
  std::vector<Vec3> skinned;
  applySkin(skin, moved, skinned);
  for (std::size_t v = 0; v < surface.size(); ++v)
  {
    EXPECT_LT((skinned[v] - (rotation * surface[v] + shift)).norm(), 1e-12);
  }
  // Areas are kept: the triangle of the first three vertices.
  const double before = (surface[1] - surface[0]).cross(surface[2] - surface[0]).norm();
  const double after = (skinned[1] - skinned[0]).cross(skinned[2] - skinned[0]).norm();
  EXPECT_NEAR(after, before, 1e-12);
}

TEST(Skinning, TetBodiesUseBarycentricCoordinates)
{
  const TetMesh mesh = makeTetBox(3, 3, 3, 0.1);
  std::vector<Vec3> vertices = test::randomVectors(50, 0.15, 9);
  std::vector<std::int32_t> tetOf(vertices.size(), 0);
  for (std::size_t v = 0; v < vertices.size(); ++v)
  {
    vertices[v] += Vec3::Constant(0.15); // inside the box, plus a few near its faces
    // The enclosing tet, by brute force (the filter uses a VTK locator).
    for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    {
      const Tet& k = mesh.tets[t];
      const std::array<Vec3, 4> p = { mesh.points[std::size_t(k[0])], mesh.points[std::size_t(k[1])],
        mesh.points[std::size_t(k[2])], mesh.points[std::size_t(k[3])] };
      const double V = signedTetVolume(p[0], p[1], p[2], p[3]);
      const double b0 = signedTetVolume(vertices[v], p[1], p[2], p[3]) / V;
      const double b1 = signedTetVolume(p[0], vertices[v], p[2], p[3]) / V;
      const double b2 = signedTetVolume(p[0], p[1], vertices[v], p[3]) / V;
      const double b3 = signedTetVolume(p[0], p[1], p[2], vertices[v]) / V;
      if (std::min({ b0, b1, b2, b3 }) >= 0.0)
      {
        tetOf[v] = static_cast<std::int32_t>(t);
        break;
      }
    }
  }
  const Skin skin = bindToTets(mesh.points, mesh.tets, vertices, tetOf);
  EXPECT_EQ(skin.outsideCount, 0u);
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(-1.1, Vec3(0, 1, 1).normalized()).toRotationMatrix();
  std::vector<Vec3> moved = mesh.points;
  for (Vec3& p : moved)
  {
    p = rotation * p + Vec3(1, 2, 3);
  }
  std::vector<Vec3> rest, skinned;
  applySkin(skin, mesh.points, rest);
  applySkin(skin, moved, skinned);
  for (std::size_t v = 0; v < vertices.size(); ++v)
  {
    EXPECT_LT((rest[v] - vertices[v]).norm(), 1e-13);
    EXPECT_LT((skinned[v] - (rotation * vertices[v] + Vec3(1, 2, 3))).norm(), 1e-12);
  }
}

/// A non-rigid deformation in the span of 1, x, y, z, xy, yz, zx, xyz (trilinear in every
/// lattice cell): it stretches, shears and bends, changing lengths and areas.
Vec3 trilinearDeformation(const Vec3& p)
{
  return Vec3(1.2 * p.x() + 0.3 * p.x() * p.y(), 0.9 * p.y() + 0.2 * p.y() * p.z() + 0.1 * p.z(),
    p.z() + 0.25 * p.x() * p.y() * p.z() - 0.15 * p.z() * p.x());
}

TEST(Skinning, LatticeFollowsANonRigidTrilinearDeformationExactly)
{
  // Trilinear weights reproduce any trilinear field exactly, inside a cell and extrapolated
  // from the nearest full one: deforming the particles by such a map moves every bound vertex
  // by the same map, although lengths and areas change by 10-30%.
  const double r = 0.5;
  const Lattice lattice = latticeOf(gridAround(0.6, 0.1), [&](const Vec3& p) { return p.norm() < r; });
  std::vector<Vec3> surface = test::randomVectors(200, 1.0, 13);
  for (std::size_t v = 0; v < surface.size(); ++v)
  {
    surface[v] = (v % 2 ? r : 0.6 * r) * surface[v].normalized(); // on the sphere and inside
  }
  const Skin skin = bindToLattice(lattice, surface);
  EXPECT_GT(skin.outsideCount, 0u);
  EXPECT_LT(skin.outsideCount, surface.size());
  std::vector<Vec3> deformed = lattice.points;
  for (Vec3& p : deformed)
  {
    p = trilinearDeformation(p);
  }
  std::vector<Vec3> skinned;
  applySkin(skin, deformed, skinned);
  for (std::size_t v = 0; v < surface.size(); ++v)
  {
    EXPECT_LT((skinned[v] - trilinearDeformation(surface[v])).norm(), 1e-12) << v;
  }
  const double before = (surface[1] - surface[0]).cross(surface[2] - surface[0]).norm();
  const double after = (skinned[1] - skinned[0]).cross(skinned[2] - skinned[0]).norm();
  EXPECT_GT(std::abs(after / before - 1.0), 0.05); // not a rigid motion
}

TEST(Skinning, TetBodiesInterpolateANonRigidDeformationLinearlyPerTet)
{
  // Under a non-affine deformation of the tet body a bound vertex moves to the barycentric
  // mean of its tet's moved corners, with coordinates computed here from volume ratios; that is
  // not the deformation of the vertex itself (linear interpolation error, checked to be > 1e-4).
  const TetMesh mesh = makeTetBox(3, 3, 3, 0.1);
  std::vector<Vec3> vertices = test::randomVectors(40, 0.14, 17);
  std::vector<std::int32_t> tetOf(vertices.size(), -1);
  std::vector<std::array<double, 4>> bary(vertices.size());
  for (std::size_t v = 0; v < vertices.size(); ++v)
  {
    vertices[v] += Vec3::Constant(0.15);
    for (std::size_t t = 0; t < mesh.tets.size() && tetOf[v] < 0; ++t)
    {
      const Tet& k = mesh.tets[t];
      const std::array<Vec3, 4> p = { mesh.points[std::size_t(k[0])], mesh.points[std::size_t(k[1])],
        mesh.points[std::size_t(k[2])], mesh.points[std::size_t(k[3])] };
      const double V = signedTetVolume(p[0], p[1], p[2], p[3]);
      const std::array<double, 4> b = { signedTetVolume(vertices[v], p[1], p[2], p[3]) / V,
        signedTetVolume(p[0], vertices[v], p[2], p[3]) / V, signedTetVolume(p[0], p[1], vertices[v], p[3]) / V,
        signedTetVolume(p[0], p[1], p[2], vertices[v]) / V };
      if (*std::min_element(b.begin(), b.end()) >= 0.0)
      {
        tetOf[v] = static_cast<std::int32_t>(t);
        bary[v] = b;
      }
    }
    ASSERT_GE(tetOf[v], 0);
  }
  const Skin skin = bindToTets(mesh.points, mesh.tets, vertices, tetOf);
  std::vector<Vec3> moved = mesh.points;
  for (Vec3& p : moved)
  {
    p = trilinearDeformation(p) + Vec3(0.01 * std::sin(20 * p.z()), 0.0, 0.0);
  }
  std::vector<Vec3> skinned;
  applySkin(skin, moved, skinned);
  double interpolationError = 0.0;
  for (std::size_t v = 0; v < vertices.size(); ++v)
  {
    const Tet& k = mesh.tets[std::size_t(tetOf[v])];
    Vec3 expected = Vec3::Zero();
    for (int c = 0; c < 4; ++c)
    {
      expected += bary[v][std::size_t(c)] * moved[std::size_t(k[c])];
    }
    EXPECT_LT((skinned[v] - expected).norm(), 1e-12) << v;
    const Vec3 exact = trilinearDeformation(vertices[v]) + Vec3(0.01 * std::sin(20 * vertices[v].z()), 0.0, 0.0);
    interpolationError = std::max(interpolationError, (skinned[v] - exact).norm());
  }
  EXPECT_GT(interpolationError, 1e-4);
}

TEST(Skinning, LatticeWithoutFullCellsIsRefused)
{
  LatticeGrid grid;
  grid.nodes = { 3, 3, 3 };
  std::vector<char> flags(grid.nodeCount(), 0);
  flags[grid.nodeIndex(1, 1, 1)] = 1;
  const Lattice lonely = buildLattice(grid, flags);
  EXPECT_THROW(bindToLattice(lonely, { Vec3(1, 1, 1) }), InvalidInputError);
}

} // namespace
} // namespace softbody
