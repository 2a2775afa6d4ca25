// A tetrahedral mesh as core sees it, its validation, and its preparation for simulation.
#pragma once

#include "softbody/common/geometry.h"

#include <cstddef>
#include <string>
#include <vector>

namespace softbody
{

struct TetMesh
{
  std::vector<Vec3> points; ///< rest positions [m]
  std::vector<Tet> tets;    ///< indices into points
};

/// What is wrong (or merely odd) with a mesh. Counts only; nothing is changed.
struct TetMeshReport
{
  std::size_t nonFinitePoints = 0; ///< points with a NaN or infinite coordinate
  std::size_t badIndexTets = 0;    ///< tets referring to a missing point or repeating one
  std::size_t invertedTets = 0;    ///< negative signed volume (not degenerate)
  std::size_t degenerateTets = 0;  ///< |V| below degenerateRelativeVolume * mean |V|
  std::size_t unusedPoints = 0;    ///< points that belong to no tet
  std::ptrdiff_t firstInvertedTet = -1;
  std::ptrdiff_t firstDegenerateTet = -1;
  double totalVolume = 0.0; ///< sum of |V| [m^3]
  double minAbsVolume = 0.0;
  double maxAbsVolume = 0.0;
};

/// Default threshold for degenerate tets, relative to the mean tet volume.
constexpr double kDegenerateRelativeVolume = 1e-8;

TetMeshReport inspectTetMesh(const TetMesh& mesh,
  double degenerateRelativeVolume = kDegenerateRelativeVolume);

enum class InvertedTetPolicy
{
  Reorient, ///< swap two corners of each inverted tet in core's copy (the input is untouched)
  Refuse    ///< throw InvalidInputError
};

/// Validates a mesh and returns a simulation-ready copy: throws InvalidInputError for an empty
/// mesh, non-finite coordinates, bad indices, degenerate tets, and (by policy) inverted tets.
/// Anything fixed or tolerated is described in `warnings`.
TetMesh prepareTetMesh(TetMesh mesh, InvertedTetPolicy policy, std::vector<std::string>& warnings);

} // namespace softbody
