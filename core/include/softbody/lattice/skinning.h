// Skinning a render surface onto a simulated body: every surface vertex is bound once to a few
// particles with weights, x_v = sum_k w_k x_p(k). The weights are trilinear coordinates in a
// lattice cell or barycentric coordinates in a tet, extrapolated for vertices outside their
// cell or tet, so they sum to 1 and reproduce every affine map exactly: a rigid motion (or any
// affine deformation) of the body moves the surface exactly the same way.
#pragma once

#include "softbody/common/geometry.h"
#include "softbody/lattice/lattice.h"

#include <cstdint>
#include <vector>

namespace softbody
{

struct Skin
{
  std::vector<std::int32_t> offsets;   ///< vertex v uses entries offsets[v] .. offsets[v+1]
  std::vector<std::int32_t> particles;
  std::vector<double> weights;
  std::size_t vertexCount() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  std::size_t outsideCount = 0; ///< vertices bound to the nearest cell/tet rather than their own
};

/// Binds each vertex to the 8 particles of its lattice cell when all 8 exist ("full" cell),
/// otherwise to the nearest full cell (nearest in the grid's Chebyshev metric, found for all
/// cells at once by a breadth-first sweep: linear in the number of cells). Throws
/// InvalidInputError when the lattice has no full cell.
Skin bindToLattice(const Lattice& lattice, const std::vector<Vec3>& vertices);

/// Binds vertex v to the 4 corners of tet tetOfVertex[v] (its enclosing or nearest tet, found by
/// the caller, e.g. with a VTK cell locator) with barycentric coordinates.
Skin bindToTets(const std::vector<Vec3>& points, const std::vector<Tet>& tets,
  const std::vector<Vec3>& vertices, const std::vector<std::int32_t>& tetOfVertex);

/// The skinned vertex positions for the current particle positions (parallel gather).
void applySkin(const Skin& skin, const std::vector<Vec3>& particlePositions, std::vector<Vec3>& vertices);

/// The corrections against the floor and obstacles are in skin_correction.h.

} // namespace softbody
