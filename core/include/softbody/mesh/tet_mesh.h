// A tetrahedral mesh as core sees it, its validation, and its preparation for simulation.
#pragma once

#include "softbody/common/geometry.h"

#include <array>
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
  /// Not degenerate, but a dihedral angle below the sliver threshold (see kMinDihedralDegrees).
  std::size_t sliverTets = 0;
  std::ptrdiff_t firstInvertedTet = -1;
  std::ptrdiff_t firstDegenerateTet = -1;
  std::ptrdiff_t worstSliverTet = -1; ///< the tet with the smallest dihedral angle of all slivers
  /// Smallest dihedral angle over the valid, non-degenerate tets [degrees]; 0 when there is none.
  double minDihedralDegrees = 0.0;
  double totalVolume = 0.0; ///< sum of |V| [m^3]
  double minAbsVolume = 0.0;
  double maxAbsVolume = 0.0;
};

/// Default threshold for degenerate tets, relative to the mean tet volume.
constexpr double kDegenerateRelativeVolume = 1e-8;

/// Default threshold for slivers [degrees]: a tet whose smallest dihedral angle is below it is
/// refused. A sliver's volume gradients are huge against its volume (the volume term's stiffness
/// grows like 1 / angle^2), so one such tet makes XPBD's volume ratios explode (-1.5e5 .. 2e5 on
/// Delaunay 3D's tetrahedralization of ParaView's default Sphere, whose worst angle is 1.9e-6
/// degrees) and Mass-Spring's stable step collapse. 0.1 degrees keeps every public mesh of
/// ../shared/data (worst: IPC's bunny.msh, 0.227 degrees; armadillo_4k 2.5, Armadillo13K 3.2,
/// sphere5K 6.8; TetGen's quality meshes stay above about 5) and refuses only tets no mesher
/// keeps on purpose. The mesh-quality report's sliver flag (kSliverDihedralDegrees, 5 degrees)
/// is a warning level; this is a refusal level.
constexpr double kMinDihedralDegrees = 0.1;

/// True when the tet's four indices are distinct points of a mesh of `pointCount` points.
bool tetIndicesValid(const Tet& tet, std::size_t pointCount);

/// The six dihedral angles [degrees] of a tet, one per edge (01, 02, 03, 12, 13, 23): the angle
/// between the two faces that share the edge. Orientation-independent (an inverted tet has
/// the same angles); 0 where a face has collapsed.
std::array<double, 6> tetDihedralAnglesDegrees(
  const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3);

/// Smallest of tetDihedralAnglesDegrees [degrees]. Regular tet: acos(1/3) = 70.53.
double tetMinDihedralAngleDegrees(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3);

TetMeshReport inspectTetMesh(const TetMesh& mesh,
  double degenerateRelativeVolume = kDegenerateRelativeVolume,
  double minDihedralDegrees = kMinDihedralDegrees);

enum class InvertedTetPolicy
{
  Reorient, ///< swap two corners of each inverted tet in core's copy (the input is untouched)
  Refuse    ///< throw InvalidInputError
};

/// Validates a mesh and returns a simulation-ready copy: throws InvalidInputError for an empty
/// mesh, non-finite coordinates, bad indices, degenerate tets, slivers (a dihedral angle below
/// kMinDihedralDegrees), and (by policy) inverted tets.
/// Anything fixed or tolerated is described in `warnings`.
TetMesh prepareTetMesh(TetMesh mesh, InvertedTetPolicy policy, std::vector<std::string>& warnings);

} // namespace softbody
