// The body a PBD/XPBD simulation is built from: particles, tets and explicit links, what the
// tets are made of, masses, pins and conditions.
#pragma once

#include "softbody/common/geometry.h"
#include "softbody/material/material.h"
#include "softbody/scene/conditions.h"

#include <array>
#include <cstdint>
#include <vector>

namespace softbody
{

/// A uniform Physical material of water's density, the particle engine's default.
inline MaterialSettings defaultParticleMaterial()
{
  MaterialSettings material;
  material.physical.density = 1000.0;
  return material;
}

struct PbdBody
{
  std::vector<Vec3> points; ///< rest positions [m]
  std::vector<Tet> tets;    ///< may be empty; each contributes its volume and its 6 edges
  std::vector<std::array<std::int32_t, 2>> links; ///< explicit distance links (line cells)
  std::vector<double> linkStiffnessScale;         ///< empty, or a factor per explicit link
  /// Per-point mass [kg]; empty = the material's density times the tet volumes, distributed
  /// as it says.
  std::vector<double> pointMass;
  /// What the tets are made of, in Physical mode, as a mass-spring body's material: density
  /// (uniform or per tet) and mass distribution for the masses; under XPBD the model, Young's
  /// modulus and Poisson's ratio (uniform or per tet) set the tets' constraints when
  /// PbdSettings::elasticFromMaterial says so, which a continuum model always does. Its damping
  /// time is not read: PBD damps through PbdSettings::damping.
  MaterialSettings material = defaultParticleMaterial();
  /// Empty or one flag per point. Pinned points are fixed (inverse mass 0) when the attachment
  /// is hard (stiffness 1 / compliance 0), otherwise attached to their rest position.
  std::vector<char> pinned;
  /// Optional triangles a body without tets collides through (cloth: two per grid cell),
  /// two-sided. Tet bodies collide through their boundary faces, found at set-up; points in
  /// neither a tet nor one of these collide as spheres of PbdSettings::particleRadius.
  std::vector<std::array<std::int32_t, 3>> surfaceTriangles;
  /// Loads and boundary conditions on sets of the points: held components are kinematic
  /// (moved where their condition says, each substep), loads external forces.
  std::vector<Condition> conditions;
};

} // namespace softbody
