// TetGen through core: closed surfaces become positively oriented tets filling exactly the
// enclosed volume; open, non-manifold and self-intersecting surfaces are refused with a message.
#include "softbody/common/errors.h"
#include "softbody/mesh/tetrahedralize.h"

#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstdio>
#include <map>

using namespace softbody;

namespace
{
using Triangles = std::vector<std::array<std::int32_t, 3>>;

struct Surface
{
  std::vector<Vec3> points;
  Triangles triangles;
};

/// Icosahedron subdivided `levels` times and projected on the sphere of radius r; outward.
Surface icosphere(int levels, double r)
{
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  Surface s;
  s.points = { { -1, t, 0 }, { 1, t, 0 }, { -1, -t, 0 }, { 1, -t, 0 }, { 0, -1, t }, { 0, 1, t },
    { 0, -1, -t }, { 0, 1, -t }, { t, 0, -1 }, { t, 0, 1 }, { -t, 0, -1 }, { -t, 0, 1 } };
  s.triangles = { { 0, 11, 5 }, { 0, 5, 1 }, { 0, 1, 7 }, { 0, 7, 10 }, { 0, 10, 11 },
    { 1, 5, 9 }, { 5, 11, 4 }, { 11, 10, 2 }, { 10, 7, 6 }, { 7, 1, 8 }, { 3, 9, 4 },
    { 3, 4, 2 }, { 3, 2, 6 }, { 3, 6, 8 }, { 3, 8, 9 }, { 4, 9, 5 }, { 2, 4, 11 }, { 6, 2, 10 },
    { 8, 6, 7 }, { 9, 8, 1 } };
  for (int l = 0; l < levels; ++l)
  {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end())
        return it->second;
      s.points.push_back(0.5 * (s.points[a] + s.points[b]));
      return mid[key] = static_cast<int>(s.points.size()) - 1;
    };
    Triangles next;
    for (const auto& f : s.triangles)
    {
      const int a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
      next.push_back({ f[0], a, c });
      next.push_back({ f[1], b, a });
      next.push_back({ f[2], c, b });
      next.push_back({ a, b, c });
    }
    s.triangles = next;
  }
  for (Vec3& p : s.points)
    p = r * p.normalized();
  return s;
}

/// Torus of radii R (center line) and r (tube) on an nu x nv grid; outward.
Surface torus(double R, double r, int nu, int nv)
{
  Surface s;
  const double pi = std::acos(-1.0);
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j)
    {
      const double u = 2 * pi * i / nu, v = 2 * pi * j / nv;
      s.points.emplace_back(
        (R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v));
    }
  auto id = [&](int i, int j) { return ((i % nu) * nv) + (j % nv); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j)
    {
      s.triangles.push_back({ id(i, j), id(i + 1, j), id(i + 1, j + 1) });
      s.triangles.push_back({ id(i, j), id(i + 1, j + 1), id(i, j + 1) });
    }
  return s;
}

/// Volume enclosed by a closed, outward surface (divergence theorem): sum p0 . (p1 x p2) / 6.
double enclosedVolume(const Surface& s)
{
  double v = 0.0;
  for (const auto& f : s.triangles)
    v += s.points[f[0]].dot(s.points[f[1]].cross(s.points[f[2]])) / 6.0;
  return v;
}

/// Sum of tet volumes; fails the test on any non-positive tet.
double checkedTetVolume(const TetMesh& mesh)
{
  double total = 0.0;
  std::size_t nonPositive = 0;
  for (const Tet& t : mesh.tets)
  {
    const double v = signedTetVolume(
      mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], mesh.points[t[3]]);
    nonPositive += v > 0.0 ? 0 : 1;
    total += v;
  }
  EXPECT_EQ(nonPositive, 0u) << "every tet must be positively oriented";
  return total;
}

/// The boundary faces of a tet mesh (faces used by one tet) must form a closed surface.
void expectClosedBoundary(const TetMesh& mesh)
{
  std::map<std::array<int, 3>, int> faces;
  for (const Tet& t : mesh.tets)
    for (int skip = 0; skip < 4; ++skip)
    {
      std::array<int, 3> f;
      int k = 0;
      for (int c = 0; c < 4; ++c)
        if (c != skip)
          f[k++] = t[c];
      std::sort(f.begin(), f.end());
      ++faces[f];
    }
  std::vector<Vec3> pts = mesh.points;
  Triangles boundary;
  for (const auto& [f, n] : faces)
  {
    ASSERT_LE(n, 2) << "a face shared by more than two tets";
    if (n == 1)
      boundary.push_back({ f[0], f[1], f[2] });
  }
  // Orientation of sorted faces is arbitrary: check closedness (edges used twice) only.
  std::map<std::pair<int, int>, int> edges;
  for (const auto& f : boundary)
    for (int k = 0; k < 3; ++k)
      ++edges[std::minmax(f[k], f[(k + 1) % 3])];
  for (const auto& [e, n] : edges)
    ASSERT_EQ(n, 2) << "boundary edge " << e.first << "-" << e.second << " is used " << n << " times";
}

std::string messageOf(const Surface& s, const TetrahedralizeOptions& o = {})
{
  try
  {
    tetrahedralizeSurface(s.points, s.triangles, o);
  }
  catch (const InvalidInputError& e)
  {
    return e.what();
  }
  return "";
}
} // namespace

TEST(Tetrahedralize, SphereFillsTheEnclosedVolume)
{
  const double pi = std::acos(-1.0);
  const Surface s = icosphere(4, 1.0); // 5120 triangles
  TetrahedralizeOptions o;
  o.maxRadiusEdgeRatio = 1.5;
  o.maxTetVolume = 0.001;
  const TetMesh mesh = tetrahedralizeSurface(s.points, s.triangles, o);
  ASSERT_GT(mesh.tets.size(), 1000u);
  const double v = checkedTetVolume(mesh);
  const double polyhedron = enclosedVolume(s), sphere = 4.0 / 3.0 * pi;
  RecordProperty("tets", static_cast<int>(mesh.tets.size()));
  std::printf("sphere: %zu points, %zu tets, volume %.9f, polyhedron %.9f (rel. error %.2e), "
              "sphere %.6f (rel. error %.2e)\n",
    mesh.points.size(), mesh.tets.size(), v, polyhedron, std::abs(v - polyhedron) / polyhedron,
    sphere, std::abs(v - sphere) / sphere);
  EXPECT_NEAR(v, polyhedron, 1e-9 * polyhedron); // the same polyhedron, filled exactly
  EXPECT_NEAR(v, sphere, 0.01 * sphere);         // and close to the smooth sphere
  expectClosedBoundary(mesh);
}

TEST(Tetrahedralize, TorusFillsTheEnclosedVolume)
{
  const double pi = std::acos(-1.0);
  const Surface s = torus(1.0, 0.3, 96, 32);
  TetrahedralizeOptions o;
  o.minDihedralAngle = 10.0;
  o.preserveBoundary = true;
  const TetMesh mesh = tetrahedralizeSurface(s.points, s.triangles, o);
  const double v = checkedTetVolume(mesh);
  const double polyhedron = enclosedVolume(s), analytic = 2 * pi * pi * 1.0 * 0.3 * 0.3;
  std::printf("torus: %zu points, %zu tets, volume %.9f, polyhedron %.9f (rel. error %.2e), "
              "torus %.6f (rel. error %.2e)\n",
    mesh.points.size(), mesh.tets.size(), v, polyhedron, std::abs(v - polyhedron) / polyhedron,
    analytic, std::abs(v - analytic) / analytic);
  EXPECT_NEAR(v, polyhedron, 1e-9 * polyhedron);
  EXPECT_NEAR(v, analytic, 0.03 * analytic);
  expectClosedBoundary(mesh);
  // Y: no Steiner point on the boundary, so every surface point is kept and the boundary
  // carries exactly the input triangles' vertices.
  EXPECT_GE(mesh.points.size(), s.points.size());
}

TEST(Tetrahedralize, VolumeBoundRefines)
{
  const Surface s = icosphere(2, 1.0);
  TetrahedralizeOptions coarse, fine;
  fine.maxTetVolume = 0.0005;
  const std::size_t a = tetrahedralizeSurface(s.points, s.triangles, coarse).tets.size();
  const std::size_t b = tetrahedralizeSurface(s.points, s.triangles, fine).tets.size();
  EXPECT_GT(b, 4 * a);
}

TEST(Tetrahedralize, StrictSettingsStopAtTheAddedPointsBound)
{
  // Ratio 1.2 with 18 degrees makes TetGen 1.5 refine without end on a sphere; the bound on
  // added points (switch S) ends it, and the stats say so.
  const Surface s = icosphere(3, 1.0);
  TetrahedralizeOptions o;
  o.maxRadiusEdgeRatio = 1.2;
  o.minDihedralAngle = 18.0;
  o.maxAddedPoints = 5000;
  TetrahedralizeStats stats;
  const TetMesh mesh = tetrahedralizeSurface(s.points, s.triangles, o, &stats);
  EXPECT_EQ(stats.surfacePoints, s.points.size());
  EXPECT_EQ(stats.addedPoints, 5000u);
  EXPECT_TRUE(stats.addedPointsLimitReached);
  EXPECT_NEAR(checkedTetVolume(mesh), enclosedVolume(s), 1e-9);
}

TEST(Tetrahedralize, OpenSurfaceIsRefused)
{
  Surface s = icosphere(1, 1.0);
  s.triangles.pop_back(); // a hole of three boundary edges
  const std::string m = messageOf(s);
  EXPECT_NE(m.find("3 boundary edges"), std::string::npos) << m;
  EXPECT_NE(m.find("open"), std::string::npos) << m;
}

TEST(Tetrahedralize, NonManifoldSurfaceIsRefused)
{
  Surface s = icosphere(1, 1.0);
  // A fin: one more triangle on an existing edge, to a new point.
  s.points.emplace_back(3.0, 0.0, 0.0);
  const auto& f = s.triangles[0];
  s.triangles.push_back({ f[0], f[1], static_cast<std::int32_t>(s.points.size() - 1) });
  const std::string m = messageOf(s);
  EXPECT_NE(m.find("1 non-manifold edges"), std::string::npos) << m;
}

TEST(Tetrahedralize, InconsistentOrientationIsRefused)
{
  Surface s = icosphere(1, 1.0);
  std::swap(s.triangles[3][1], s.triangles[3][2]);
  const std::string m = messageOf(s);
  EXPECT_NE(m.find("3 edges with inconsistently oriented"), std::string::npos) << m;
}

TEST(Tetrahedralize, SelfIntersectingSurfaceIsRefused)
{
  // Two overlapping spheres as one surface: each closed and manifold, together intersecting.
  Surface a = icosphere(1, 1.0), b = icosphere(1, 1.0);
  const auto offset = static_cast<std::int32_t>(a.points.size());
  for (const Vec3& p : b.points)
    a.points.push_back(p + Vec3(0.8, 0.1, 0.05));
  for (auto f : b.triangles)
    a.triangles.push_back({ f[0] + offset, f[1] + offset, f[2] + offset });
  ASSERT_TRUE(checkClosedManifold(a.points, a.triangles).ok());
  const std::string m = messageOf(a);
  EXPECT_NE(m.find("intersect"), std::string::npos) << m;
}

TEST(Tetrahedralize, BadInputsAndOptionsAreRefused)
{
  Surface s = icosphere(0, 1.0);
  EXPECT_NE(messageOf(Surface{}).find("at least 4"), std::string::npos);
  TetrahedralizeOptions o;
  o.maxRadiusEdgeRatio = 0.5;
  EXPECT_NE(messageOf(s, o).find("MaxRadiusEdgeRatio"), std::string::npos);
  o = {};
  o.maxTetVolume = std::nan("");
  EXPECT_NE(messageOf(s, o).find("MaxTetVolume"), std::string::npos);
  Surface nan = s;
  nan.points[0].x() = std::nan("");
  EXPECT_NE(messageOf(nan).find("NaN"), std::string::npos);
  Surface bad = s;
  bad.triangles[0][0] = 99;
  EXPECT_NE(messageOf(bad).find("missing points"), std::string::npos);
  // Unused points are ignored, not meshed.
  Surface extra = s;
  extra.points.emplace_back(10.0, 10.0, 10.0);
  const TetMesh mesh = tetrahedralizeSurface(extra.points, extra.triangles, {});
  for (const Vec3& p : mesh.points)
    EXPECT_LT(p.norm(), 2.0);
}
