// Closed triangle surface -> tetrahedral mesh, through TetGen (Hang Si, TetGen 1.5).
#pragma once

#include "softbody/mesh/tet_mesh.h"

#include <array>
#include <cstdint>
#include <vector>

namespace softbody
{

/// TetGen quality settings, in the terms of its command-line switches.
struct TetrahedralizeOptions
{
  /// Largest radius-edge ratio of a tet (switch q, first value); 0 = no quality refinement.
  /// TetGen needs > ~1.1 to terminate; 2.0 is its default and a good start.
  double maxRadiusEdgeRatio = 2.0;
  /// Smallest dihedral angle [deg] TetGen tries to keep (switch q, second value); 0 = TetGen's
  /// default (0 in 1.5). Values above ~18 deg may not terminate.
  double minDihedralAngle = 0.0;
  /// Largest tet volume in the surface's units cubed (switch a); 0 = unbounded.
  double maxTetVolume = 0.0;
  /// Keep the boundary triangles as given: no Steiner points on the surface (switch Y).
  bool preserveBoundary = false;
  /// Most points TetGen may add to meet the quality and volume bounds (switch S); 0 = no limit.
  /// Strict combinations (e.g. ratio 1.2 with 18 deg) make TetGen 1.5 refine without end; the
  /// bound makes it stop with the best mesh so far. 200000 added points is ~1.2 M tets, ~4 s.
  std::size_t maxAddedPoints = 200000;
  /// Silence TetGen's console report (switch Q).
  bool quiet = true;
};

/// What tetrahedralizeSurface did besides returning the mesh.
struct TetrahedralizeStats
{
  std::size_t surfacePoints = 0; ///< points of the input surface given to TetGen
  std::size_t addedPoints = 0;   ///< Steiner points TetGen added (inside and on the boundary)
  bool addedPointsLimitReached = false; ///< the quality/volume bounds may not be met
};

/// How a triangle surface fails to be closed and manifold. Counts only.
struct SurfaceCheck
{
  std::size_t boundaryEdges = 0;      ///< edges used by one triangle (holes)
  std::size_t nonManifoldEdges = 0;   ///< edges used by three or more triangles
  std::size_t inconsistentEdges = 0;  ///< edges two triangles run through in the same direction
  std::size_t degenerateTriangles = 0; ///< triangles repeating a corner
  std::size_t badIndexTriangles = 0;  ///< triangles naming a missing point
  std::size_t nonFinitePoints = 0;
  bool ok() const
  {
    return boundaryEdges == 0 && nonManifoldEdges == 0 && inconsistentEdges == 0 &&
      degenerateTriangles == 0 && badIndexTriangles == 0 && nonFinitePoints == 0;
  }
};

/// Counts the defects that make a surface unusable as a TetGen boundary (see SurfaceCheck).
SurfaceCheck checkClosedManifold(
  const std::vector<Vec3>& points, const std::vector<std::array<std::int32_t, 3>>& triangles);

/// Fills the volume bounded by a closed, manifold, consistently oriented triangle surface with
/// tetrahedra. Points the triangles do not use are ignored. The output tets are all positively
/// oriented. Throws InvalidInputError for an empty, open, non-manifold or self-intersecting
/// surface, bad options, or any TetGen failure (TetGen never exits the process here).
TetMesh tetrahedralizeSurface(const std::vector<Vec3>& points,
  const std::vector<std::array<std::int32_t, 3>>& triangles, const TetrahedralizeOptions& options,
  TetrahedralizeStats* stats = nullptr);

} // namespace softbody
