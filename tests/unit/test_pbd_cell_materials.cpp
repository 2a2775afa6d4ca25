// Per-cell materials under PBD and XPBD: a bar of two materials under XPBD rests where the static
// solve of the same cells does (and where neither material alone would), a per-cell density gives
// each particle the mass Mass-Spring gives it, and values the formulation would not read, or that
// contradict each other, are refused with the reason.
#include "softbody/common/errors.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"
#include "softbody/pbd/pbd_simulation.h"
#include "static_equilibrium.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cstdio>

using namespace softbody;

namespace
{

constexpr double kLength = 0.5, kTop = 4.0e5, kBottom = 1.0e5;

/// A bar (2 x 2 x 10 cubic cells of 5 cm) hanging from its top face, its upper half four times
/// stiffer than its lower half: each tet's Young's modulus from its centroid's height.
struct TwoMaterialBar
{
  TetMesh mesh = makeTetBox(2, 2, 10, 0.05);
  std::vector<char> top = test::pointsWhere(mesh.points, [](const Vec3& p) { return p.z() > kLength - 1e-9; });

  MaterialSettings material(MaterialModel model, bool perCell) const
  {
    MaterialSettings m;
    m.model = model;
    m.physical = { kBottom, 0.3, 1000.0, 0.0 };
    m.massDistribution = MassDistribution::LumpedVolume;
    for (std::size_t t = 0; perCell && t < mesh.tets.size(); ++t)
    {
      double z = 0.0;
      for (std::int32_t p : mesh.tets[t])
      {
        z += mesh.points[static_cast<std::size_t>(p)].z() / 4;
      }
      m.cells.youngsModulus.push_back(z > kLength / 2 ? kTop : kBottom);
    }
    return m;
  }

  Body pbdBody(const MaterialSettings& m) const
  {
    Body body;
    body.mesh.points = mesh.points;
    body.mesh.tets = mesh.tets;
    body.pinned = top;
    body.material = m;
    return body;
  }

  double staticDrop(const MaterialSettings& m) const
  {
    Body body;
    body.mesh = mesh;
    body.pinned = top;
    body.material = m;
    return bottomDrop(test::staticEquilibrium(body));
  }

  double xpbdDrop(const MaterialSettings& m) const
  {
    PbdSettings settings;
    settings.elasticFromMaterial = true;
    settings.collisions.mode = CollisionMode::Off;
    settings.reportConvergence = false;
    settings.substeps = 16;
    settings.damping = 5.0; // to rest within the run
    PbdSimulation sim(pbdBody(m), settings);
    sim.advance(2.5);
    return bottomDrop(sim.state().positions);
  }

  double bottomDrop(const std::vector<Vec3>& positions) const
  {
    return test::meanDrop(mesh.points, positions, [](const Vec3& p) { return p.z() < 1e-9; });
  }
};

std::string refusal(const Body& body, const PbdSettings& settings)
{
  return test::refusalOf<PbdSimulation>(body, settings);
}

} // namespace

TEST(PbdCellMaterials, XpbdTwoMaterialBarRestsWhereTheStaticSolveOfItsCellsDoes)
{
  // XPBD's rest state is its law's equilibrium within 1 % of the sag at 16 substeps
  // (XpbdContinuum.HangingBarRests...), so the per-cell moduli must put it there, and not at
  // either uniform material's drop (which differ from it by a factor 1.5-2.5).
  const TwoMaterialBar bar;
  for (MaterialModel model : { MaterialModel::SpringNetwork, MaterialModel::Corotated, MaterialModel::StableNeoHookean })
  {
    const double equilibrium = bar.staticDrop(bar.material(model, true));
    const double xpbd = bar.xpbdDrop(bar.material(model, true));
    const double soft = bar.xpbdDrop(bar.material(model, false));
    std::printf("%s: two-material bar drops %.4e m under XPBD, %.4e m in the static solve of the same "
      "cells (%+.2e); %.4e m all of the softer material\n", materialModelName(model), xpbd,
      equilibrium, xpbd / equilibrium - 1, soft);
    EXPECT_NEAR(xpbd, equilibrium, 0.01 * equilibrium) << materialModelName(model);
    EXPECT_GT(soft, 1.5 * xpbd) << materialModelName(model);
  }
}

TEST(PbdCellMaterials, PerCellDensityGivesEachParticleTheMassMassSpringGivesIt)
{
  // PBD without elasticity reads only the densities: its particles' masses are Mass-Spring's.
  const TwoMaterialBar bar;
  MaterialSettings material = bar.material(MaterialModel::SpringNetwork, false);
  for (std::size_t t = 0; t < bar.mesh.tets.size(); ++t)
  {
    material.cells.density.push_back(t % 3 == 0 ? 3000.0 : 500.0);
  }
  Body massSpringBody;
  massSpringBody.mesh = bar.mesh;
  massSpringBody.material = material;
  const MassSpringSimulation massSpring(massSpringBody, SceneSettings{});
  PbdSettings pbd;
  pbd.formulation = PbdFormulation::Pbd;
  Body body = bar.pbdBody(material);
  body.pinned.clear();
  const PbdSimulation particles(body, pbd);
  double total = 0.0;
  for (std::size_t i = 0; i < bar.mesh.points.size(); ++i)
  {
    const double m = 1.0 / particles.inverseMasses()[i];
    EXPECT_NEAR(m, massSpring.masses()[i], 1e-12 * massSpring.masses()[i]) << "point " << i;
    total += m;
  }
  EXPECT_NEAR(total, massSpring.totalMass(), 1e-12 * total);
}

TEST(PbdCellMaterials, ValuesTheFormulationWouldNotReadAreRefused)
{
  const TwoMaterialBar bar;
  PbdSettings compliances; // XPBD with its constraint types' compliances: E is not read
  const Body perCell = bar.pbdBody(bar.material(MaterialModel::SpringNetwork, true));
  EXPECT_NE(refusal(perCell, compliances).find("would be ignored"), std::string::npos)
    << refusal(perCell, compliances);
  PbdSettings fromMaterial;
  fromMaterial.elasticFromMaterial = true;
  EXPECT_EQ(refusal(perCell, fromMaterial), "");

  // Point masses and per-cell densities contradict each other.
  Body massive = bar.pbdBody(bar.material(MaterialModel::SpringNetwork, false));
  massive.pointMass.assign(massive.mesh.points.size(), 0.1);
  massive.material.cells.density.assign(massive.mesh.tets.size(), 1000.0);
  EXPECT_NE(refusal(massive, fromMaterial).find("both point masses"), std::string::npos)
    << refusal(massive, fromMaterial);

  // A per-cell Poisson's ratio Corotated cannot take under XPBD names its cell.
  Body corotated = bar.pbdBody(bar.material(MaterialModel::Corotated, false));
  corotated.material.cells.poissonRatio.assign(corotated.mesh.tets.size(), 0.3);
  corotated.material.cells.poissonRatio[11] = -0.25;
  EXPECT_NE(refusal(corotated, fromMaterial).find("PoissonRatio -0.25 (cell 11) gives Corotated's"),
    std::string::npos) << refusal(corotated, fromMaterial);
  // And a wrong count is refused as under Mass-Spring.
  corotated.material.cells.poissonRatio.assign(3, 0.3);
  EXPECT_NE(refusal(corotated, fromMaterial).find("has 3 values for"), std::string::npos)
    << refusal(corotated, fromMaterial);
}
