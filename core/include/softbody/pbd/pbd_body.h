// The body a PBD/XPBD simulation is built from: particles, tets and explicit links, masses
// pins and conditions.
#pragma once

#include "softbody/common/geometry.h"
#include "softbody/material/material.h" // MassDistribution
#include "softbody/scene/conditions.h"

#include <array>
#include <cstdint>
#include <vector>

namespace softbody
{

struct PbdBody
{
  std::vector<Vec3> points; ///< rest positions [m]
  std::vector<Tet> tets;    ///< may be empty; each contributes its volume and its 6 edges
  std::vector<std::array<std::int32_t, 2>> links; ///< explicit distance links (line cells)
  std::vector<double> linkStiffnessScale;         ///< empty, or a factor per explicit link
  /// Per-point mass [kg]; empty = density times the tet volumes, distributed as chosen.
  std::vector<double> pointMass;
  double density = 1000.0; ///< [kg/m^3]
  MassDistribution massDistribution = MassDistribution::AverageIncidentVolume;
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
