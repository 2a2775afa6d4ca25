// Tet volume gradients and the connectivity derived from tets.
#include "softbody/mesh/mesh_generators.h"
#include "softbody/mesh/topology.h"
#include "softbody/mesh/components.h"
#include "softbody/common/errors.h"

#include <gtest/gtest.h>

#include <set>
#include <sstream>

using namespace softbody;

TEST(Geometry, VolumeGradientsMatchFiniteDifferences)
{
  const std::array<Vec3, 4> p{ Vec3(0.1, -0.2, 0.0), Vec3(1.2, 0.1, 0.3), Vec3(0.2, 0.9, -0.1),
    Vec3(0.3, 0.2, 1.1) };
  const auto g = tetVolumeGradients(p[0], p[1], p[2], p[3]);
  const double eps = 1e-6;
  for (int corner = 0; corner < 4; ++corner)
  {
    for (int axis = 0; axis < 3; ++axis)
    {
      auto plus = p, minus = p;
      plus[corner][axis] += eps;
      minus[corner][axis] -= eps;
      const double fd = (signedTetVolume(plus[0], plus[1], plus[2], plus[3]) -
                          signedTetVolume(minus[0], minus[1], minus[2], minus[3])) / (2 * eps);
      EXPECT_NEAR(g[corner][axis], fd, 1e-9) << "corner " << corner << " axis " << axis;
    }
  }
  EXPECT_LT((g[0] + g[1] + g[2] + g[3]).norm(), 1e-14);
}

TEST(Topology, KuhnBoxHasTheAnalyticEdgeCount)
{
  // Axis edges 3n(n+1)^2, one diagonal per face 3n^2(n+1), one body diagonal per cube n^3.
  for (int n : { 1, 2, 5 })
  {
    const TetMesh mesh = makeTetBox(n, n, n, 0.1);
    const Topology topology = buildTopology(mesh.points.size(), mesh.tets);
    const std::size_t expected = 3 * n * (n + 1) * (n + 1) + 3 * n * n * (n + 1) + n * n * n;
    EXPECT_EQ(topology.edges.size(), expected) << "n = " << n;
    EXPECT_EQ(mesh.tets.size(), std::size_t(6 * n * n * n));
  }
}

TEST(Topology, IncidenceListsAreConsistent)
{
  const TetMesh mesh = makeTetBox(3, 2, 2, 0.1);
  const Topology topology = buildTopology(mesh.points.size(), mesh.tets);
  std::set<std::pair<int, int>> unique;
  for (const Edge& e : topology.edges)
  {
    EXPECT_LT(e.a, e.b);
    unique.insert({ e.a, e.b });
  }
  EXPECT_EQ(unique.size(), topology.edges.size());
  // Every edge appears in the rows of both its ends, every tet corner in its point's row.
  EXPECT_EQ(topology.vertexEdges.items.size(), 2 * topology.edges.size());
  EXPECT_EQ(topology.vertexTetCorners.items.size(), 4 * topology.tets.size());
  for (std::size_t i = 0; i < topology.vertexCount; ++i)
  {
    for (int k = topology.vertexEdges.offsets[i]; k < topology.vertexEdges.offsets[i + 1]; ++k)
    {
      const Edge& e = topology.edges[topology.vertexEdges.items[k]];
      EXPECT_TRUE(e.a == int(i) || e.b == int(i));
    }
    for (int k = topology.vertexTetCorners.offsets[i]; k < topology.vertexTetCorners.offsets[i + 1]; ++k)
    {
      const int tc = topology.vertexTetCorners.items[k];
      EXPECT_EQ(topology.tets[tc / 4][tc % 4], int(i));
    }
  }
  for (std::size_t t = 0; t < topology.tets.size(); ++t)
  {
    for (int k = 0; k < 6; ++k)
    {
      const Edge& e = topology.edges[topology.tetEdges.items[6 * t + k]];
      const Tet& tet = topology.tets[t];
      EXPECT_NE(std::find(tet.begin(), tet.end(), e.a), tet.end());
      EXPECT_NE(std::find(tet.begin(), tet.end(), e.b), tet.end());
    }
  }
}

TEST(TetMesh, InspectionCountsInvertedDegenerateAndUnused)
{
  TetMesh mesh = makeTetBox(2, 1, 1, 1.0);
  std::swap(mesh.tets[0][0], mesh.tets[0][1]);     // inverted
  mesh.points.push_back(Vec3(5, 5, 5));             // unused
  const std::int32_t a = 0, b = 1, c = 2;           // collinear corners on the box's edge row
  mesh.tets.push_back({ a, b, c, mesh.tets[3][3] }); // flat: points 0,1,2 lie on one line
  const TetMeshReport report = inspectTetMesh(mesh);
  EXPECT_EQ(report.invertedTets, 1u);
  EXPECT_EQ(report.firstInvertedTet, 0);
  EXPECT_EQ(report.degenerateTets, 1u);
  EXPECT_EQ(report.firstDegenerateTet, std::ptrdiff_t(mesh.tets.size() - 1));
  EXPECT_EQ(report.unusedPoints, 1u);
}

// Slivers: four well-spread points nearly in a plane. Two diagonals of a unit square, one
// lifted by h: its volume (h / 6) is far above the degenerate threshold, but its smallest
// dihedral angle is about h radians, and its volume forces would be unbounded.
TEST(TetMesh, SliversBelowTheMinimumDihedralAngleAreRefusedWithTheWorstAngle)
{
  TetMesh mesh = makeTetBox(1, 1, 1, 1.0);
  const double regular = tetMinDihedralAngleDegrees(
    Vec3(1, 1, 1), Vec3(1, -1, -1), Vec3(-1, 1, -1), Vec3(-1, -1, 1));
  EXPECT_NEAR(regular, 70.528779, 1e-5);
  const auto first = static_cast<std::int32_t>(mesh.points.size());
  const double h = 1e-5;
  for (const Vec3& p : { Vec3(3, 0, 0), Vec3(4, 1, 0), Vec3(4, 0, h), Vec3(3, 1, h) })
  {
    mesh.points.push_back(p);
  }
  mesh.tets.push_back({ first, first + 1, first + 2, first + 3 });
  const Tet& sliver = mesh.tets.back();
  if (signedTetVolume(mesh.points[sliver[0]], mesh.points[sliver[1]], mesh.points[sliver[2]],
        mesh.points[sliver[3]]) < 0.0)
  {
    std::swap(mesh.tets.back()[2], mesh.tets.back()[3]);
  }
  const double worst = tetMinDihedralAngleDegrees(mesh.points[sliver[0]], mesh.points[sliver[1]],
    mesh.points[sliver[2]], mesh.points[sliver[3]]);
  EXPECT_LT(worst, kMinDihedralDegrees);
  EXPECT_GT(worst, 0.0);

  const TetMeshReport report = inspectTetMesh(mesh);
  EXPECT_EQ(report.degenerateTets, 0u);
  EXPECT_EQ(report.sliverTets, 1u);
  EXPECT_EQ(report.worstSliverTet, std::ptrdiff_t(mesh.tets.size() - 1));
  EXPECT_DOUBLE_EQ(report.minDihedralDegrees, worst);

  std::vector<std::string> warnings;
  std::string message;
  try
  {
    prepareTetMesh(mesh, InvertedTetPolicy::Refuse, warnings);
  }
  catch (const InvalidInputError& e)
  {
    message = e.what();
  }
  std::ostringstream angle;
  angle << worst;
  EXPECT_NE(message.find("1 of the 7 tetrahedra are slivers"), std::string::npos) << message;
  EXPECT_NE(message.find("worst is " + angle.str() + " degrees, cell 6"), std::string::npos) << message;
  EXPECT_NE(message.find("Tetrahedralize Surface (TetGen)"), std::string::npos) << message;

  // A stated threshold below the sliver's angle lets it through; the box alone always passes.
  EXPECT_EQ(inspectTetMesh(mesh, kDegenerateRelativeVolume, 0.5 * worst).sliverTets, 0u);
  mesh.tets.pop_back();
  EXPECT_NO_THROW(prepareTetMesh(mesh, InvertedTetPolicy::Refuse, warnings));
}

TEST(TetMesh, DegenerateMessageNamesTheRemeshingFilter)
{
  TetMesh mesh = makeTetBox(2, 1, 1, 1.0);
  mesh.tets.push_back({ 0, 1, 2, mesh.tets[3][3] }); // points 0, 1, 2 lie on one line
  std::vector<std::string> warnings;
  std::string message;
  try
  {
    prepareTetMesh(mesh, InvertedTetPolicy::Reorient, warnings);
  }
  catch (const InvalidInputError& e)
  {
    message = e.what();
  }
  EXPECT_NE(message.find("degenerate"), std::string::npos) << message;
  EXPECT_NE(message.find("Tetrahedralize Surface (TetGen)"), std::string::npos) << message;
}

TEST(Components, CellsSharingAPointAreOneBodyNumberedByFirstCell)
{
  // Cells: {0,1} {5,6} {1,2} {7} {2,3} -> bodies {0,2,4} (points 0-3), {1} (5,6), {3} (7).
  const std::vector<std::int64_t> offsets{ 0, 2, 4, 6, 7, 9 };
  const std::vector<std::int64_t> points{ 0, 1, 5, 6, 1, 2, 7, 2, 3 };
  const softbody::Components c = softbody::connectedComponents(8, offsets, points);
  EXPECT_EQ(c.count, 3);
  EXPECT_EQ(c.ofCell, (std::vector<std::int32_t>{ 0, 1, 0, 2, 0 }));
  // Point 4 is in no cell: it joins nothing. A bad index is refused with its value.
  EXPECT_THROW(softbody::connectedComponents(3, offsets, points), softbody::InvalidInputError);
}
