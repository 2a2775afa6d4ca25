// Whether a body can carry its own weight: rho g H / E from its extent along gravity, the
// set-up's warning for a held body that cannot, and the blow-up message that names it.
#include "softbody/massspring/mass_spring_setup.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/material/self_weight.h"
#include "softbody/mesh/mesh_generators.h"

#include <gtest/gtest.h>

#include <algorithm>

using namespace softbody;

namespace
{

/// Two columns side by side, 1.0 m and 0.5 m tall, of 0.1 m cells.
Body twoColumns(double youngsModulus)
{
  const TetMesh tall = makeTetBox(2, 2, 10, 0.1, Vec3(0.0, 0.0, 0.0));
  const TetMesh shortOne = makeTetBox(2, 2, 5, 0.1, Vec3(1.0, 0.0, 0.0));
  Body body;
  body.mesh = tall;
  const auto offset = static_cast<std::int32_t>(tall.points.size());
  body.mesh.points.insert(body.mesh.points.end(), shortOne.points.begin(), shortOne.points.end());
  for (Tet t : shortOne.tets)
  {
    for (std::int32_t& v : t)
    {
      v += offset;
    }
    body.mesh.tets.push_back(t);
  }
  body.material.physical.youngsModulus = youngsModulus;
  body.material.physical.density = 1000.0;
  return body;
}

bool mentions(const std::vector<std::string>& warnings, const std::string& text)
{
  return std::any_of(warnings.begin(), warnings.end(),
    [&](const std::string& w) { return w.find(text) != std::string::npos; });
}

} // namespace

TEST(SelfWeight, IsRhoGHOverEOfTheMostStrainedBodyAlongGravity)
{
  const Body body = twoColumns(1.0e4);
  const MassSpringSetup setup = prepareMassSpring(body, SceneSettings{});
  const SelfWeight down = selfWeightStrain(setup.mesh, setup.constants.restVolume, body.material, Vec3(0, 0, -9.81));
  EXPECT_NEAR(down.height, 1.0, 1e-12) << "the taller column";
  EXPECT_NEAR(down.strain, 1000.0 * 9.81 * 1.0 / 1.0e4, 1e-12);
  // Gravity along x: each column is 0.2 m across it.
  const SelfWeight sideways = selfWeightStrain(setup.mesh, setup.constants.restVolume, body.material, Vec3(-9.81, 0, 0));
  EXPECT_NEAR(sideways.height, 0.2, 1e-12);
  // Per-cell moduli are averaged over the body's volume.
  Body mixed = body;
  const std::size_t tallTets = 2 * 2 * 10 * 6; // the tall column's come first
  mixed.material.cells.youngsModulus.assign(body.mesh.tets.size(), 1.0e6); // the short one stiff
  for (std::size_t t = 0; t < tallTets; ++t)
  {
    mixed.material.cells.youngsModulus[t] = t < tallTets / 2 ? 3.0e4 : 1.0e4; // equal volumes
  }
  const SelfWeight averaged = selfWeightStrain(setup.mesh, setup.constants.restVolume, mixed.material, Vec3(0, 0, -9.81));
  EXPECT_NEAR(averaged.youngsModulus, 2.0e4, 1e-8);
  // The thesis's raw constants have no E: nothing to say.
  Body raw = body;
  raw.material.mode = MaterialMode::Raw;
  EXPECT_EQ(selfWeightStrain(setup.mesh, setup.constants.restVolume, raw.material, Vec3(0, 0, -9.81)).strain, 0.0);
}

TEST(SelfWeight, AHeldBodyThatCannotCarryItselfIsWarnedOfWithTheNumbersAndRemedies)
{
  SceneSettings onFloor;
  onFloor.floorEnabled = true;
  const MassSpringSimulation soft(twoColumns(5.0e3), onFloor); // strain 1.96
  const std::vector<std::string>& warnings = soft.warnings();
  EXPECT_TRUE(mentions(warnings, "cannot carry its own weight")) << "no warning";
  EXPECT_TRUE(mentions(warnings, "= 1.96")) << "the strain is quoted";
  EXPECT_TRUE(mentions(warnings, "YoungsModulus 5e+03 Pa")) << "the typed modulus is quoted";
  EXPECT_TRUE(mentions(warnings, "units")) << "the usual cause is named";
  EXPECT_FALSE(mentions(MassSpringSimulation(twoColumns(1.0e5), onFloor).warnings(), "own weight"));
  // Falling freely nothing carries it: no floor, no fixed points, no warning.
  SceneSettings free;
  free.floorEnabled = false;
  EXPECT_FALSE(mentions(MassSpringSimulation(twoColumns(5.0e3), free).warnings(), "own weight"));
  // Hung from fixed points it is held too.
  Body hung = twoColumns(5.0e3);
  hung.pinned.assign(hung.mesh.points.size(), 0);
  for (std::size_t i = 0; i < hung.mesh.points.size(); ++i)
  {
    hung.pinned[i] = hung.mesh.points[i].z() > 0.99 ? 1 : 0;
  }
  EXPECT_TRUE(mentions(MassSpringSimulation(hung, free).warnings(), "cannot carry its own weight"));
}

TEST(SelfWeight, ABlowUpOfABodyThatCannotCarryItselfSaysSoRatherThanReduceTheStep)
{
  DynamicState state;
  state.time = 4.0;
  SelfWeight collapsing;
  collapsing.strain = 12.5;
  collapsing.height = 115.0;
  collapsing.density = 1100.0;
  collapsing.youngsModulus = 1.0e5;
  const std::string collapsed = divergenceMessage(state, 1e6, true, 0.01, 0.02, collapsing);
  EXPECT_NE(collapsed.find("cannot carry its own weight"), std::string::npos) << collapsed;
  EXPECT_NE(collapsed.find("115 m tall"), std::string::npos) << collapsed;
  EXPECT_EQ(collapsed.find("reduce TimeStep"), std::string::npos) << collapsed;
  SelfWeight carried = collapsing;
  carried.strain = 0.1;
  const std::string unstable = divergenceMessage(state, 1e6, true, 0.01, 0.02, carried);
  EXPECT_NE(unstable.find("reduce TimeStep"), std::string::npos) << unstable;
}
