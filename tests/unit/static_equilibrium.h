// The static equilibrium of a body under gravity with nothing to collide with: the answer the
// XPBD tests' rest states converge to.
#pragma once

#include "softbody/massspring/mass_spring_simulation.h"

#include <vector>

namespace softbody::test
{

/// Where the Static integrator puts `body`'s points, Newton solved to `tolerance`.
inline std::vector<Vec3> staticEquilibrium(const Body& body, double tolerance = 1e-9)
{
  SceneSettings scene;
  scene.collisions.mode = CollisionMode::Off;
  scene.integrator = Integrator::Static;
  scene.implicit.tolerance = tolerance;
  MassSpringSimulation sim(body, scene);
  sim.advance(0.1);
  return sim.positions();
}

} // namespace softbody::test
