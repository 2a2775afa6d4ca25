// Mass distribution and inverse-mass truncation.
#include "softbody/material/mass.h"
#include "softbody/mesh/mesh_generators.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

using namespace softbody;

namespace
{
std::vector<double> tetVolumes(const TetMesh& mesh)
{
  std::vector<double> v;
  for (const Tet& t : mesh.tets)
  {
    v.push_back(signedTetVolume(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], mesh.points[t[3]]));
  }
  return v;
}
} // namespace

TEST(Mass, BothSchemesSumToTheTotal)
{
  const TetMesh mesh = makeTetBox(4, 3, 2, 0.05);
  const Topology topology = buildTopology(mesh.points.size(), mesh.tets);
  for (auto scheme : { MassDistribution::AverageIncidentVolume, MassDistribution::LumpedVolume })
  {
    const PointMasses m = distributeMass(topology, tetVolumes(mesh), 2.5, scheme, 0.0, {});
    EXPECT_NEAR(std::accumulate(m.mass.begin(), m.mass.end(), 0.0), 2.5, 1e-12);
    EXPECT_NEAR(m.totalMass, 2.5, 1e-12);
    for (std::size_t i = 0; i < m.mass.size(); ++i)
    {
      EXPECT_NEAR(m.inverseMass[i] * m.mass[i], 1.0, 1e-12);
    }
  }
}

TEST(Mass, LumpedMassIsAQuarterOfTheIncidentVolume)
{
  const TetMesh mesh = makeTetBox(2, 2, 2, 1.0);
  const Topology topology = buildTopology(mesh.points.size(), mesh.tets);
  const double density = 3.0;
  const PointMasses m = distributeMass(topology, tetVolumes(mesh), density * 8.0,
    MassDistribution::LumpedVolume, 0.0, {});
  // The center point (1,1,1) touches all 8 cubes' tets that meet there: a quarter of their
  // volume times the density. Count its tets directly.
  const int center = 1 + 3 * (1 + 3 * 1);
  const int tetsAround = topology.vertexTetCorners.offsets[center + 1] - topology.vertexTetCorners.offsets[center];
  EXPECT_NEAR(m.mass[center], density * tetsAround * (1.0 / 6.0) / 4.0, 1e-12);
}

TEST(Mass, TruncationCapsInverseMassAndPinsAreImmovable)
{
  const TetMesh mesh = makeTetBox(3, 3, 3, 0.1);
  const Topology topology = buildTopology(mesh.points.size(), mesh.tets);
  const auto volumes = tetVolumes(mesh);
  const PointMasses free = distributeMass(topology, volumes, 1.0, MassDistribution::LumpedVolume, 0.0, {});
  const double wMax = *std::max_element(free.inverseMass.begin(), free.inverseMass.end());
  const double cap = 0.5 * wMax;
  std::vector<char> pinned(mesh.points.size(), 0);
  pinned[0] = 1;
  const PointMasses capped = distributeMass(topology, volumes, 1.0, MassDistribution::LumpedVolume, cap, pinned);
  EXPECT_GT(capped.truncatedCount, 0u);
  EXPECT_GT(capped.totalMass, 1.0); // truncated points got heavier
  for (double w : capped.inverseMass)
  {
    EXPECT_LE(w, cap * (1 + 1e-12));
  }
  EXPECT_EQ(capped.inverseMass[0], 0.0);
  EXPECT_GT(capped.mass[0], 0.0);
}

TEST(Mass, AverageIncidentVolumeOfEqualTetsIsUniform)
{
  // Every tet of a box split into Kuhn tets has the same volume, so the mean volume of each
  // point's tets is that volume for every point (corners are in 1 tet, inner points in 24): the
  // thesis's scheme gives every point the same mass, the lumped one does not.
  const TetMesh mesh = makeTetBox(2, 2, 2, 0.05);
  const Topology topology = buildTopology(mesh.points.size(), mesh.tets);
  const PointMasses m = distributeMass(topology, tetVolumes(mesh), 2.7, MassDistribution::AverageIncidentVolume, 0.0, {});
  for (double mass : m.mass)
  {
    EXPECT_NEAR(mass, 2.7 / 27.0, 1e-15);
  }
  const PointMasses lumped = distributeMass(topology, tetVolumes(mesh), 2.7, MassDistribution::LumpedVolume, 0.0, {});
  EXPECT_GT(*std::max_element(lumped.mass.begin(), lumped.mass.end()),
    4.0 * *std::min_element(lumped.mass.begin(), lumped.mass.end()));
}
