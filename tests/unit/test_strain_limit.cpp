// Strain limiting: violated springs are pulled back to the limit, weighted by inverse mass.
#include "softbody/massspring/strain_limit.h"
#include "softbody/material/mass.h"
#include "softbody/massspring/mass_spring_forces.h"
#include "softbody/mesh/mesh_generators.h"
#include "test_support.h"

#include <gtest/gtest.h>

using namespace softbody;

TEST(StrainLimit, StretchedBodyIsBroughtWithinTheLimit)
{
  const TetMesh mesh = makeTetBox(4, 4, 4, 0.1);
  const Topology topology = buildTopology(mesh.points.size(), mesh.tets);
  std::vector<std::string> warnings;
  const ElementConstants c = computeElementConstants(topology, mesh.points, MaterialSettings{}, warnings);
  const PointMasses m = distributeMass(topology, c.restVolume, 1.0, MassDistribution::LumpedVolume, 0.0, {});

  // Stretch along x by 1.5 with noise; limit 1.1.
  std::vector<Vec3> x = test::jitter(mesh.points, 0.005);
  for (Vec3& p : x)
  {
    p.x() *= 1.5;
  }
  std::vector<Vec3> v(x.size(), Vec3::Zero());
  StrainLimitScratch scratch;
  ASSERT_GT(maxStretchRatio(topology, c, x), 1.4);
  const std::size_t violated = limitStrain(topology, c, m.inverseMass, 1.1, 200, false, 1e-3, x, v, scratch);
  EXPECT_GT(violated, 0u);
  EXPECT_LT(maxStretchRatio(topology, c, x), 1.1 * 1.002);
  for (const Vec3& vi : v)
  {
    EXPECT_EQ(vi.norm(), 0.0); // positions only when not asked to adjust velocities
  }
}

TEST(StrainLimit, CorrectionIsWeightedByInverseMass)
{
  // One tet, corner 0 pinned (w = 0): stretching edge 0-1 moves only corner 1.
  TetMesh mesh;
  mesh.points = { Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1) };
  mesh.tets = { { 0, 1, 2, 3 } };
  const Topology topology = buildTopology(4, mesh.tets);
  std::vector<std::string> warnings;
  const ElementConstants c = computeElementConstants(topology, mesh.points, MaterialSettings{}, warnings);
  std::vector<double> w = { 0.0, 1.0, 1.0, 1.0 };
  std::vector<Vec3> x = mesh.points;
  x[1].x() = 2.0; // edge 0-1 at twice its length, others stretched too
  std::vector<Vec3> v(4, Vec3::Zero());
  StrainLimitScratch scratch;
  limitStrain(topology, c, w, 1.2, 1, true, 0.01, x, v, scratch);
  EXPECT_EQ(x[0], mesh.points[0]);
  EXPECT_LT(x[1].x(), 2.0);
  // The velocity follows the position change when asked (position-based integrators).
  EXPECT_NEAR(v[1].x(), (x[1].x() - 2.0) / 0.01, 1e-9);
}
