// The scene every method shares: its derived rules, and what they mean for a body at the floor
// under Mass-Spring and PBD/XPBD alike (the floor holds a falling body only while collisions
// are on; a floor nothing touches is not read, so it is not refused either).
#include "softbody/common/errors.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"
#include "softbody/pbd/pbd_simulation.h"
#include "softbody/scene/scene.h"
#include "pbd_test_bodies.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <string>

namespace softbody
{
namespace
{

/// A 15 cm tet box whose bottom starts 5 cm above the floor at z = 0.
Body massSpringBox()
{
  Body body;
  body.mesh = makeTetBox(3, 3, 3, 0.05, Vec3(0, 0, 0.05));
  return body;
}

double lowestZ(const std::vector<Vec3>& points)
{
  double lowest = std::numeric_limits<double>::infinity();
  for (const Vec3& p : points)
  {
    lowest = std::min(lowest, p.z());
  }
  return lowest;
}

/// The lowest point after 0.3 s of falling (0.44 m of free fall: far past the floor).
double lowestAfterFall(const Scene& scene, bool pbd)
{
  if (pbd)
  {
    PbdSettings settings;
    static_cast<Scene&>(settings) = scene;
    PbdSimulation sim(test::pbdBoxBody(3, 0.05, Vec3(0, 0, 0.05)), settings);
    sim.advance(0.3);
    return lowestZ(sim.positions());
  }
  SceneSettings settings;
  static_cast<Scene&>(settings) = scene;
  MassSpringSimulation sim(massSpringBox(), settings);
  sim.advance(0.3);
  return lowestZ(sim.positions());
}

TEST(Scene, RulesFollowTheCollisionMode)
{
  struct Expected
  {
    CollisionMode mode;
    bool on, bodies, self;
  };
  for (const Expected& e : { Expected{ CollisionMode::Off, false, false, false },
         Expected{ CollisionMode::Obstacles, true, false, false },
         Expected{ CollisionMode::ObstaclesAndBodies, true, true, false },
         Expected{ CollisionMode::ObstaclesBodiesAndSelf, true, true, true } })
  {
    Scene scene;
    scene.collisions.mode = e.mode;
    EXPECT_EQ(scene.collisions.on(), e.on);
    EXPECT_EQ(scene.collisions.bodiesCollide(), e.bodies);
    EXPECT_EQ(scene.collisions.selfCollides(), e.self);
    scene.floorEnabled = false;
    EXPECT_FALSE(scene.floorActive());
    scene.floorEnabled = true;
    EXPECT_EQ(scene.floorActive(), e.on);
  }
}

TEST(Scene, EveryMethodRestsOnTheFloorOnlyWhileCollisionsAreOn)
{
  for (bool pbd : { false, true })
  {
    Scene scene;
    scene.floorEnabled = true;
    const double held = lowestAfterFall(scene, pbd);
    // Held at the floor within its contact margin (a tenth of an edge, 5 mm, at most).
    EXPECT_GT(held, -1e-3) << (pbd ? "PBD" : "Mass-Spring");
    EXPECT_LT(held, 0.01) << (pbd ? "PBD" : "Mass-Spring");
    scene.collisions.mode = CollisionMode::Off;
    // Falls through: 0.05 m - g t^2 / 2 = -0.39 m for a free body.
    EXPECT_LT(lowestAfterFall(scene, pbd), -0.3) << (pbd ? "PBD" : "Mass-Spring");
  }
}

TEST(Scene, AFloorNothingTouchesIsNotRefused)
{
  for (bool pbd : { false, true })
  {
    Scene scene;
    scene.floorEnabled = true;
    scene.floor.normal = Vec3::Zero();
    try
    {
      lowestAfterFall(scene, pbd);
      ADD_FAILURE() << "a zero FloorNormal was accepted with the floor active";
    }
    catch (const InvalidInputError& error)
    {
      EXPECT_NE(std::string(error.what()).find("FloorNormal"), std::string::npos) << error.what();
    }
    scene.collisions.mode = CollisionMode::Off;
    EXPECT_NO_THROW(lowestAfterFall(scene, pbd)) << (pbd ? "PBD" : "Mass-Spring");
  }
}

} // namespace
} // namespace softbody
