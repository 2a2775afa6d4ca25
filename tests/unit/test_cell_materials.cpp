// Per-cell materials: a bar of two materials hangs by the sum of its halves' elongations, a
// per-cell density gives each tet its own mass, uniform values given per cell change nothing,
// the renumbered stepper takes the cells with their tets, and a bad value is refused naming the
// cell and the value.
#include "softbody/common/errors.h"
#include "softbody/massspring/mass_spring_reordered.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

using namespace softbody;

namespace
{

constexpr double kLength = 1.0, kRho = 1000.0, kG = 9.81;

/// A 2 x 2 x 20 bar of 5 cm cells along z hanging from its top face; `material(z)` gives each
/// tet's (E, rho) from its centroid height.
struct HangingBar
{
  Body body;
  SceneSettings scene;
  explicit HangingBar(MaterialModel model)
  {
    body.mesh = makeTetBox(2, 2, 20, 0.05);
    body.material.model = model;
    body.material.physical.poissonRatio = 0.0;
    body.material.physical.density = kRho;
    body.material.massDistribution = MassDistribution::LumpedVolume;
    body.pinned = test::pointsWhere(body.mesh.points, [](const Vec3& p) { return p.z() > kLength - 1e-9; });
    scene.integrator = Integrator::Static;
    scene.collisions.mode = CollisionMode::Off;
    scene.implicit.tolerance = 1e-10;
  }
  double centroidZ(std::size_t t) const
  {
    double z = 0.0;
    for (std::int32_t p : body.mesh.tets[t])
    {
      z += body.mesh.points[static_cast<std::size_t>(p)].z() / 4;
    }
    return z;
  }
  double elongation(const Simulation& sim) const
  {
    return test::meanDrop(body.mesh.points, sim.positions(), [](const Vec3& p) { return p.z() < 1e-9; });
  }
};

std::string refusal(const Body& body, const SceneSettings& scene)
{
  return test::refusalOf<MassSpringSimulation>(body, scene);
}

} // namespace

TEST(CellMaterials, TwoMaterialBarHangsByTheSumOfItsHalves)
{
  // Uniaxial stress rho g z (nu = 0) over E(z): the elongation is
  // rho g / 2 [ (L/2)^2 / E_bottom + (L^2 - (L/2)^2) / E_top ] = rho g L^2 / 8 (1/E_b + 3/E_t).
  const double top = 4.0e7, bottom = 1.0e7;
  const double exact = kRho * kG * kLength * kLength / 8 * (1 / bottom + 3 / top);
  for (MaterialModel model : { MaterialModel::Corotated, MaterialModel::StableNeoHookean })
  {
    HangingBar bar(model);
    for (std::size_t t = 0; t < bar.body.mesh.tets.size(); ++t)
    {
      bar.body.material.cells.youngsModulus.push_back(bar.centroidZ(t) > kLength / 2 ? top : bottom);
    }
    MassSpringSimulation sim(bar.body, bar.scene);
    sim.advance(0.1);
    const double error = bar.elongation(sim) / exact - 1;
    std::printf("%s: two-material bar elongation error %+.3e\n", materialModelName(model), error);
    EXPECT_LT(std::abs(error), 3e-3) << materialModelName(model);
  }
}

TEST(CellMaterials, PerCellDensityGivesEachTetItsMass)
{
  HangingBar bar(MaterialModel::Corotated);
  double expected = 0.0;
  for (std::size_t t = 0; t < bar.body.mesh.tets.size(); ++t)
  {
    const double rho = bar.centroidZ(t) > kLength / 2 ? 3000.0 : 500.0;
    bar.body.material.cells.density.push_back(rho);
    const auto& tet = bar.body.mesh.tets[t];
    const auto& p = bar.body.mesh.points;
    expected += rho * signedTetVolume(p[tet[0]], p[tet[1]], p[tet[2]], p[tet[3]]);
  }
  const MassSpringSimulation sim(bar.body, bar.scene);
  EXPECT_NEAR(sim.totalMass(), expected, 1e-12 * expected);
  // The top half is six times denser: its points carry most of the mass.
  double upper = 0.0;
  for (std::size_t i = 0; i < sim.masses().size(); ++i)
  {
    upper += bar.body.mesh.points[i].z() > kLength / 2 + 1e-9 ? sim.masses()[i] : 0.0;
  }
  EXPECT_GT(upper, 0.8 * expected);
}

TEST(CellMaterials, UniformValuesGivenPerCellChangeNothing)
{
  for (MaterialModel model : { MaterialModel::SpringNetwork, MaterialModel::Corotated })
  {
    HangingBar bar(model);
    bar.body.material.physical.youngsModulus = 2.0e6;
    bar.body.material.physical.poissonRatio = 0.3;
    bar.scene.integrator = Integrator::ImplicitEuler;
    bar.scene.timeStep = 0.01;
    MassSpringSimulation uniform(bar.body, bar.scene);
    uniform.advance(0.2);
    const std::size_t tets = bar.body.mesh.tets.size();
    bar.body.material.cells = { std::vector<double>(tets, 2.0e6), std::vector<double>(tets, 0.3),
      std::vector<double>(tets, kRho) };
    MassSpringSimulation perCell(bar.body, bar.scene);
    perCell.advance(0.2);
    // The per-cell path sums springs' shares per tet and masses as rho V: the same numbers up
    // to rounding, which Newton's stopping test may carry a little further.
    EXPECT_LT(test::maxDistance(uniform.positions(), perCell.positions()), 1e-9 * kLength)
      << materialModelName(model);
  }
}

TEST(CellMaterials, RenumberedStepperTakesTheCellsWithTheirTets)
{
  HangingBar bar(MaterialModel::StableNeoHookean);
  for (std::size_t t = 0; t < bar.body.mesh.tets.size(); ++t)
  {
    bar.body.material.cells.youngsModulus.push_back(bar.centroidZ(t) > kLength / 2 ? 4.0e7 : 1.0e7);
  }
  MassSpringSimulation inputOrder(bar.body, bar.scene);
  inputOrder.advance(0.1);
  const auto renumbered = makeMassSpringSimulation(bar.body, bar.scene);
  renumbered->advance(0.1);
  EXPECT_LT(test::maxDistance(inputOrder.positions(), renumbered->positions()), 1e-9 * kLength);
  const TetStressField a = inputOrder.stressField(), b = renumbered->stressField();
  ASSERT_EQ(a.vonMises.size(), b.vonMises.size());
  for (std::size_t t = 0; t < a.vonMises.size(); ++t)
  {
    EXPECT_NEAR(a.vonMises[t], b.vonMises[t], 1e-6 * kRho * kG * kLength) << "tet " << t;
  }
}

TEST(CellMaterials, BadValuesAreRefusedNamingTheCell)
{
  HangingBar bar(MaterialModel::Corotated);
  const std::size_t tets = bar.body.mesh.tets.size();
  Body body = bar.body;
  body.material.cells.youngsModulus.assign(tets, 1.0e6);
  body.material.cells.youngsModulus[5] = -3.0;
  EXPECT_EQ(refusal(body, bar.scene), "YoungsModulus of cell 5 must be > 0 Pa, got -3.");
  body = bar.body;
  body.material.cells.poissonRatio.assign(tets, 0.2);
  body.material.cells.poissonRatio[7] = 0.5;
  EXPECT_EQ(refusal(body, bar.scene), "PoissonRatio of cell 7 must be in (-1, 0.5), got 0.5.");
  body = bar.body;
  body.material.cells.density.assign(3, 1000.0);
  EXPECT_EQ(refusal(body, bar.scene),
    "The per-cell Density has 3 values for " + std::to_string(tets) + " tets.");
  body = bar.body;
  body.material.model = MaterialModel::SpringNetwork;
  body.material.cells.poissonRatio.assign(tets, 0.3);
  body.material.cells.poissonRatio[2] = 0.1;
  SceneSettings explicitScene = bar.scene;
  explicitScene.integrator = Integrator::EulerCromer;
  const MassSpringSimulation network(body, explicitScene);
  ASSERT_FALSE(network.warnings().empty());
  EXPECT_NE(network.warnings().front().find("in 1 cells (the first: cell 2, 0.1)"), std::string::npos)
    << network.warnings().front();
}
