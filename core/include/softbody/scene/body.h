// The body every method is built from: its rest mesh (tets, or particles and links), what it
// is made of, its masses, pins and conditions. Mass-spring, the finite-element models and the
// particle engine (PBD/XPBD) all take this one type; the parts only the particle engine reads
// are marked, and the mass-spring stepper refuses a body that has them.
#pragma once

#include "softbody/material/material.h"
#include "softbody/mesh/reorder.h"
#include "softbody/mesh/tet_mesh.h"
#include "softbody/scene/conditions.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace softbody
{

struct Body
{
  /// Rest positions [m] and tets. Tets may be empty for the particle engine, whose bodies can
  /// be links, cloth or loose particles.
  TetMesh mesh;
  /// Particle engine only: explicit distance links (line cells) and empty or a stiffness factor
  /// per link.
  std::vector<std::array<std::int32_t, 2>> links;
  std::vector<double> linkStiffnessScale;
  /// Particle engine only: per-point mass [kg]; empty = the material's density times the tet
  /// volumes, distributed as the material says (the only way mass-spring bodies get mass).
  std::vector<double> pointMass;
  /// Particle engine only: triangles a body without tets collides through (cloth: two per grid
  /// cell), two-sided. Tet bodies collide through their boundary faces, found at set-up.
  std::vector<std::array<std::int32_t, 3>> surfaceTriangles;
  /// What the tets are made of: model, Young's modulus, Poisson's ratio and density, uniform or
  /// per tet. The particle engine in PBD (not XPBD) mode reads its density only.
  MaterialSettings material;
  /// Empty or one flag per point (nonzero: pinned). Pins are Fixed conditions too.
  std::vector<char> pinned;
  /// Loads and boundary conditions on sets of the points.
  std::vector<Condition> conditions;

  /// The particle-engine-only parts the body has, named for a message ("12 links, point
  /// masses"); empty when it has none.
  std::string particleOnlyParts() const;
};

/// The body stored in `reordering`'s order: points and everything per point (masses, pins,
/// condition point sets) renumbered, tets and their per-tet material in the tet order (input
/// order when the reordering has none), links and triangles renumbered in their own order.
Body reorderBody(const Body& body, const Reordering& reordering);

} // namespace softbody
