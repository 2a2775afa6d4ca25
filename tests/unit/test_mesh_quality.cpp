// Mesh quality report: dihedral angles against closed forms, sliver / inverted / degenerate
// flags on a hand-built mesh, histograms, and the mass-spring numbers against the simulation.
#include "softbody/common/errors.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"
#include "softbody/stability/stability_report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

using namespace softbody;

namespace
{
const double kRadToDeg = 180.0 / std::acos(-1.0);

std::size_t sum(const std::vector<std::size_t>& counts)
{
  return std::accumulate(counts.begin(), counts.end(), std::size_t(0));
}

/// Appends a tet of the given corners (offset by `at`) to `mesh`, positively oriented unless
/// `invert` is set.
void addTet(TetMesh& mesh, std::array<Vec3, 4> corners, const Vec3& at, bool invert = false)
{
  const auto first = static_cast<std::int32_t>(mesh.points.size());
  for (Vec3& c : corners)
  {
    mesh.points.push_back(c + at);
  }
  Tet tet{ first, first + 1, first + 2, first + 3 };
  const double v = signedTetVolume(corners[0], corners[1], corners[2], corners[3]);
  if ((v < 0.0) != invert)
  {
    std::swap(tet[2], tet[3]);
  }
  mesh.tets.push_back(tet);
}

const std::array<Vec3, 4> kRegular{ Vec3(1, 1, 1), Vec3(1, -1, -1), Vec3(-1, 1, -1), Vec3(-1, -1, 1) };
const std::array<Vec3, 4> kRightCorner{ Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1) };
// Two crossing edges 0.02 apart in height over a span of 2: four well-spread, nearly coplanar
// points. Every edge is longer than 1, yet the tet is almost flat: the classic sliver.
const std::array<Vec3, 4> kSliver{ Vec3(-1, 0, 0), Vec3(1, 0, 0), Vec3(0, -1, 0.02), Vec3(0, 1, 0.02) };
const std::array<Vec3, 4> kFlat{ Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0) };

/// Regular, right-corner, sliver, inverted right-corner and flat tets, disjoint.
TetMesh handBuiltMesh()
{
  TetMesh mesh;
  addTet(mesh, kRegular, Vec3(0, 0, 0));
  addTet(mesh, kRightCorner, Vec3(5, 0, 0));
  addTet(mesh, kSliver, Vec3(10, 0, 0));
  addTet(mesh, kRightCorner, Vec3(15, 0, 0), /*invert=*/true);
  addTet(mesh, kFlat, Vec3(20, 0, 0));
  return mesh;
}

MaterialSettings rubber()
{
  MaterialSettings material;
  material.physical.youngsModulus = 1e5;
  material.physical.density = 1000.0;
  material.physical.dampingTime = 1e-3;
  return material;
}

/// A 3x3x3 Kuhn box whose corner (0,0,0) is pulled 90% of the way along its cube's diagonal:
/// its six tets shrink to a tenth of their volume, so that corner is the lightest point by far.
TetMesh boxWithTinyCorner()
{
  TetMesh mesh = makeTetBox(3, 3, 3, 0.1);
  mesh.points[0] = Vec3(0.09, 0.09, 0.09);
  return mesh;
}
} // namespace

TEST(MeshQuality, RegularTetDihedralAnglesAreAcosOneThird)
{
  const auto angles = tetDihedralAnglesDegrees(kRegular[0], kRegular[1], kRegular[2], kRegular[3]);
  for (double a : angles)
  {
    EXPECT_NEAR(a, std::acos(1.0 / 3.0) * kRadToDeg, 1e-12);
  }
  EXPECT_NEAR(tetMinDihedralAngleDegrees(kRegular[0], kRegular[1], kRegular[2], kRegular[3]),
    70.528779365509308, 1e-12);
}

TEST(MeshQuality, RightCornerTetAnglesAndOrientationIndependence)
{
  const auto& p = kRightCorner;
  // Edges 01, 02, 03 lie along the axes: the coordinate planes meet at 90 degrees. Edges 12,
  // 13, 23 border the slanted face (normal (1,1,1)/sqrt 3): acos(1/sqrt 3) = 54.74 degrees.
  const std::array<double, 6> expected{ 90.0, 90.0, 90.0, std::acos(1.0 / std::sqrt(3.0)) * kRadToDeg,
    std::acos(1.0 / std::sqrt(3.0)) * kRadToDeg, std::acos(1.0 / std::sqrt(3.0)) * kRadToDeg };
  const auto angles = tetDihedralAnglesDegrees(p[0], p[1], p[2], p[3]);
  for (int e = 0; e < 6; ++e)
  {
    EXPECT_NEAR(angles[e], expected[e], 1e-12) << "edge " << e;
  }
  // Swapping two corners inverts the tet but not its shape.
  EXPECT_NEAR(tetMinDihedralAngleDegrees(p[0], p[1], p[3], p[2]),
    tetMinDihedralAngleDegrees(p[0], p[1], p[2], p[3]), 1e-12);
}

TEST(MeshQuality, HistogramCountsEveryFiniteValueOnce)
{
  const Histogram h = makeHistogram({ 1.0, 2.0, 3.0, 4.0, std::nan(""), 2.5 }, 3);
  EXPECT_DOUBLE_EQ(h.min, 1.0);
  EXPECT_DOUBLE_EQ(h.max, 4.0);
  ASSERT_EQ(h.counts.size(), 3u);
  EXPECT_EQ(h.counts[0], 1u); // [1, 2)
  EXPECT_EQ(h.counts[1], 2u); // [2, 3)
  EXPECT_EQ(h.counts[2], 2u); // [3, 4], the maximum included
  EXPECT_DOUBLE_EQ(h.binCenters[0], 1.5);
  EXPECT_DOUBLE_EQ(h.binCenters[2], 3.5);

  const Histogram same = makeHistogram({ 2e-9, 2e-9 }, 4);
  EXPECT_EQ(sum(same.counts), 2u);
  EXPECT_LT(same.min, 2e-9);
  EXPECT_GT(same.max, 2e-9);
  EXPECT_EQ(sum(makeHistogram({}, 5).counts), 0u);
}

TEST(MeshQuality, HandBuiltMeshFlagsSliverInvertedAndDegenerate)
{
  const TetMesh mesh = handBuiltMesh();
  const MassSpringQualityReport r = computeMassSpringQuality(mesh, rubber(), Integrator::EulerCromer);

  ASSERT_EQ(r.minDihedralDegrees.size(), 5u);
  EXPECT_NEAR(r.minDihedralDegrees[0], 70.528779365509308, 1e-9);
  EXPECT_NEAR(r.minDihedralDegrees[1], std::acos(1.0 / std::sqrt(3.0)) * kRadToDeg, 1e-9);
  EXPECT_LT(r.minDihedralDegrees[2], kSliverDihedralDegrees);
  EXPECT_GT(r.minDihedralDegrees[2], 0.0);
  EXPECT_NEAR(r.minDihedralDegrees[3], r.minDihedralDegrees[1], 1e-9);

  EXPECT_EQ(r.sliver, (std::vector<char>{ 0, 0, 1, 0, 0 }));
  EXPECT_EQ(r.inverted, (std::vector<char>{ 0, 0, 0, 1, 0 }));
  EXPECT_EQ(r.degenerate, (std::vector<char>{ 0, 0, 0, 0, 1 }));
  EXPECT_EQ(r.sliverTets, 1u);
  EXPECT_EQ(r.invertedTets, 1u);
  EXPECT_EQ(r.degenerateTets, 1u);
  // The per-tet flags follow inspectTetMesh's definitions exactly.
  EXPECT_EQ(r.mesh.invertedTets, r.invertedTets);
  EXPECT_EQ(r.mesh.degenerateTets, r.degenerateTets);
  EXPECT_DOUBLE_EQ(r.minDihedralDegreesOverall, r.minDihedralDegrees[2]);
  EXPECT_NEAR(r.signedVolume[3], -1.0 / 6.0, 1e-15);

  // The inverted tet is measured re-oriented: it weighs what its twin (tet 1) weighs. The flat
  // tet gets no mass; everything else does.
  for (int k = 0; k < 4; ++k)
  {
    EXPECT_DOUBLE_EQ(r.inverseMass[12 + k], r.inverseMass[4 + k]);
    EXPECT_EQ(r.inverseMass[16 + k], 0.0);
  }
  EXPECT_GT(r.stableTimeStep, 0.0);

  // Histograms count every element once: 16 points with mass, 5 tets, 30 distinct edges.
  EXPECT_EQ(sum(r.inverseMassHistogram.counts), 16u);
  EXPECT_EQ(sum(r.volumeHistogram.counts), mesh.tets.size());
  EXPECT_EQ(sum(r.edgeLengthHistogram.counts), 30u);
  EXPECT_EQ(r.edgeLength.size(), 30u);
  EXPECT_LT(r.volumeHistogram.min, 0.0); // the inverted tet shows up left of zero
}

TEST(MeshQuality, BadIndicesAndNonFinitePointsAreCountedNotThrown)
{
  TetMesh mesh = makeTetBox(1, 1, 1, 1.0);
  mesh.tets.push_back({ 0, 1, 2, 99 });
  mesh.points.push_back(Vec3(std::nan(""), 0, 0));
  const auto last = static_cast<std::int32_t>(mesh.points.size() - 1);
  mesh.tets.push_back({ 0, 1, 2, last });
  MassSpringQualityReport r;
  ASSERT_NO_THROW(r = computeMassSpringQuality(mesh, rubber(), Integrator::Verlet));
  EXPECT_EQ(r.mesh.badIndexTets, 1u);
  EXPECT_TRUE(std::isnan(r.signedVolume[6]) && std::isnan(r.signedVolume[7]));
  EXPECT_EQ(sum(r.volumeHistogram.counts), 6u);
  EXPECT_GT(r.stableTimeStep, 0.0);
}

TEST(MeshQuality, BadMaterialAndSettingsThrow)
{
  MaterialSettings material = rubber();
  material.physical.youngsModulus = -1.0;
  EXPECT_THROW(computeMassSpringQuality(makeTetBox(1, 1, 1, 1.0), material, Integrator::Euler),
    InvalidInputError);
  MeshQualitySettings settings;
  settings.truncationMassBudget = -0.1;
  EXPECT_THROW(computeMassSpringQuality(makeTetBox(1, 1, 1, 1.0), rubber(), Integrator::Euler, settings),
    InvalidInputError);
}

TEST(MeshQuality, InverseMassesAndStableStepsMatchTheSimulation)
{
  TetMesh mesh = boxWithTinyCorner();
  std::swap(mesh.tets[7][0], mesh.tets[7][1]); // one inverted tet: Reorient must agree
  // Every material model: the finite-element models' step comes from their own stiffness, as
  // the set-up's does (and differs from the network's on the same mesh, checked below).
  for (auto [scheme, model] : { std::pair{ MassDistribution::AverageIncidentVolume, MaterialModel::SpringNetwork },
         std::pair{ MassDistribution::LumpedVolume, MaterialModel::SpringNetwork },
         std::pair{ MassDistribution::LumpedVolume, MaterialModel::Corotated },
         std::pair{ MassDistribution::AverageIncidentVolume, MaterialModel::StableNeoHookean } })
  {
    SCOPED_TRACE(materialModelName(model));
    MaterialSettings material = rubber();
    material.massDistribution = scheme;
    material.model = model;
    const MassSpringQualityReport r = computeMassSpringQuality(mesh, material, Integrator::Midpoint);
    EXPECT_EQ(r.invertedTets, 1u);

    SceneSettings scene;
    scene.integrator = Integrator::Midpoint;
    const auto bodyOf = [&mesh](const MaterialSettings& made) {
      Body body;
      body.mesh = mesh;
      body.material = made;
      return body;
    };
    const MassSpringSimulation plain(bodyOf(material), scene);
    EXPECT_EQ(r.inverseMass, plain.inverseMasses());
    EXPECT_DOUBLE_EQ(r.stableTimeStep, plain.estimatedStableStep());
    EXPECT_DOUBLE_EQ(r.totalMass, plain.totalMass());

    // The suggested truncation, applied in the simulation, gives the step the report predicts.
    material.maxInverseMass = r.suggestedMaxInverseMass;
    const MassSpringSimulation truncated(bodyOf(material), scene);
    EXPECT_DOUBLE_EQ(r.truncatedStableTimeStep, truncated.estimatedStableStep());
    EXPECT_DOUBLE_EQ(r.truncatedTotalMass, truncated.totalMass());
  }
  MaterialSettings corotated = rubber();
  corotated.model = MaterialModel::Corotated;
  EXPECT_NE(computeMassSpringQuality(mesh, corotated, Integrator::Midpoint).stableTimeStep,
    computeMassSpringQuality(mesh, rubber(), Integrator::Midpoint).stableTimeStep);
}

TEST(MeshQuality, SuggestedTruncationRaisesTheStableStep)
{
  const MassSpringQualityReport r =
    computeMassSpringQuality(boxWithTinyCorner(), rubber(), Integrator::EulerCromer);
  const double wMax = *std::max_element(r.inverseMass.begin(), r.inverseMass.end());
  EXPECT_DOUBLE_EQ(wMax, r.inverseMass[0]); // the shrunken corner is the lightest point
  EXPECT_LT(r.suggestedMaxInverseMass, wMax);
  EXPECT_GT(r.truncatedPoints, 0u);
  EXPECT_GT(r.truncatedStableTimeStep, r.stableTimeStep);
  EXPECT_GT(r.stableStepGain, 1.0);
  EXPECT_DOUBLE_EQ(r.stableStepGain, r.truncatedStableTimeStep / r.stableTimeStep);
  // The cap spends the whole 1% budget (the largest gain it allows) and no more.
  EXPECT_NEAR(r.truncatedTotalMass, 1.01 * r.totalMass, 1e-12 * r.totalMass);

  // A larger budget never gives a smaller step; no budget changes nothing.
  MeshQualitySettings generous;
  generous.truncationMassBudget = 0.05;
  const MassSpringQualityReport g =
    computeMassSpringQuality(boxWithTinyCorner(), rubber(), Integrator::EulerCromer, generous);
  EXPECT_GE(g.truncatedStableTimeStep, r.truncatedStableTimeStep);
  MeshQualitySettings none;
  none.truncationMassBudget = 0.0;
  const MassSpringQualityReport z =
    computeMassSpringQuality(boxWithTinyCorner(), rubber(), Integrator::EulerCromer, none);
  EXPECT_DOUBLE_EQ(z.suggestedMaxInverseMass, wMax);
  EXPECT_DOUBLE_EQ(z.truncatedStableTimeStep, z.stableTimeStep);
}
