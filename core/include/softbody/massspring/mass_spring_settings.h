// What a mass-spring simulation is built from: the body (mesh, pins, material) and the scene
// settings (integrator, step, gravity, floor, strain limit). Immutable once the stepper is made.
#pragma once

#include "softbody/common/floor_plane.h"
#include "softbody/massspring/explicit_integrators.h"
#include "softbody/material/material.h"
#include "softbody/mesh/tet_mesh.h"

#include <vector>

namespace softbody
{

struct SceneSettings
{
  Integrator integrator = Integrator::EulerCromer;
  /// [s]; 0 = automatic: the largest stable step estimate times stabilitySafety.
  double timeStep = 0.0;
  double stabilitySafety = 0.9; ///< fraction of the estimated stable step used in auto mode
  Vec3 gravity{ 0.0, 0.0, -9.81 }; ///< [m/s^2]
  bool floorEnabled = false;
  FloorPlane floor;
  /// Strain limit: maximum l / l0 of a spring (> 1); 0 disables strain limiting.
  double strainLimit = 0.0;
  int strainLimitIterations = 4;
  InvertedTetPolicy invertedTets = InvertedTetPolicy::Reorient;
  /// A state is declared exploded when a spring grows past this factor of its rest length.
  double divergenceStretch = 100.0;
  bool operator==(const SceneSettings&) const = default;
};

struct BodyDescription
{
  TetMesh mesh;
  std::vector<char> pinned; ///< empty, or one flag per mesh point (nonzero: pinned)
  MaterialSettings material;
};

} // namespace softbody
