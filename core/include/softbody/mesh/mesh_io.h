// Readers for tetrahedral meshes in files: TetGen .node/.ele and Gmsh .msh (ASCII 2.2 and 4.1).
#pragma once

#include "softbody/mesh/tet_mesh.h"

#include <cstddef>
#include <istream>
#include <string>
#include <string_view>
#include <vector>

namespace softbody
{

/// A Gmsh physical group: the mesh points its elements use (of any dimension: a physical
/// surface marks the boundary nodes a condition is put on).
struct MeshGroup
{
  int dimension = 0;
  long long tag = 0;
  std::string name;           ///< from $PhysicalNames; "Physical <dim>D <tag>" when unnamed
  std::vector<char> points;   ///< one flag per returned mesh point
};

/// What a reader met besides the tetrahedra it returns.
struct MeshFileInfo
{
  /// Gmsh: per returned tet, the physical group (0: none; the first when several) and the
  /// elementary entity of the volume element it came from. Empty for TetGen.
  std::vector<long long> tetPhysicalTag, tetEntityTag;
  /// Gmsh: every physical group that has elements, by dimension then tag.
  std::vector<MeshGroup> groups;
  std::string format;              ///< e.g. "TetGen", "Gmsh 2.2", "Gmsh 4.1"
  std::size_t skippedElements = 0; ///< points, lines, triangles, quadrangles (not volume cells)
  std::size_t convertedElements = 0; ///< hexahedra, prisms and pyramids split into tetrahedra
  /// What the reader changed, for the user (e.g. how many hexahedra it split into how many tets).
  std::vector<std::string> warnings;
};

/// `text` for an error message: at most `maxChars` characters (then "..."), every byte that is
/// not printable ASCII written as \xHH (tab as \t), so binary garbage in a file can neither
/// flood the console nor send control characters to it.
std::string printableExcerpt(std::string_view text, std::size_t maxChars = 60);

/// Reads a TetGen mesh through TetGen's own loader. `path` names the .node or the .ele file (or
/// their common base name); both must exist. Tets are returned as stored (not re-oriented), with
/// 0-based indices whatever the file's first index. Throws InvalidInputError for a missing,
/// truncated or garbled file, out-of-range indices or non-finite coordinates, and for a qhull
/// rbox header (which TetGen would read as a different format).
TetMesh readTetGenMesh(const std::string& path, MeshFileInfo* info = nullptr);

/// Reads the nodes and the volume cells of a Gmsh ASCII .msh file, format 2.x or 4.1. 4-node
/// tetrahedra (element type 4) are returned as stored; 8-node hexahedra (5), 6-node prisms (6)
/// and 5-node pyramids (7) are split into 6, 3 and 2 tetrahedra, conformingly (each quadrangle
/// face is cut along the diagonal through its lowest-numbered node, so two cells sharing it
/// cut it alike), positively oriented for a valid cell, and each conversion is counted in
/// `info->warnings`. Points, lines, triangles and quadrangles are skipped and counted; volume
/// cells of second or higher order are refused with their count. Physical groups and
/// elementary entities are kept in `info` (tags per tet, the nodes of each physical group
/// including the points, lines and surfaces it holds). Node tags are mapped to
/// contiguous indices in file order. Throws InvalidInputError, naming the line, for binary,
/// unsupported, truncated or malformed files.
TetMesh readGmshMesh(const std::string& path, MeshFileInfo* info = nullptr);

/// Same as readGmshMesh on an open stream; `name` is used in messages.
TetMesh readGmshMesh(std::istream& in, const std::string& name, MeshFileInfo* info = nullptr);

} // namespace softbody
