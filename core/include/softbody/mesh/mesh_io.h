// Readers for tetrahedral meshes in files: TetGen .node/.ele and Gmsh .msh (ASCII 2.2 and 4.1).
#pragma once

#include "softbody/mesh/tet_mesh.h"

#include <cstddef>
#include <istream>
#include <string>

namespace softbody
{

/// What a reader met besides the tetrahedra it returns.
struct MeshFileInfo
{
  std::string format;              ///< e.g. "TetGen", "Gmsh 2.2", "Gmsh 4.1"
  std::size_t skippedElements = 0; ///< elements that are not 4-node tets (triangles, lines, ...)
};

/// Reads a TetGen mesh through TetGen's own loader. `path` names the .node or the .ele file (or
/// their common base name); both must exist. Tets are returned as stored (not re-oriented), with
/// 0-based indices whatever the file's first index. Throws InvalidInputError for a missing,
/// truncated or garbled file, out-of-range indices or non-finite coordinates.
TetMesh readTetGenMesh(const std::string& path, MeshFileInfo* info = nullptr);

/// Reads the nodes and the 4-node tetrahedra (element type 4) of a Gmsh ASCII .msh file,
/// format 2.x or 4.1. Other element types are skipped and counted; node tags are mapped to
/// contiguous indices in file order; tets are returned as stored. Throws InvalidInputError,
/// naming the line, for binary, unsupported, truncated or malformed files.
TetMesh readGmshMesh(const std::string& path, MeshFileInfo* info = nullptr);

/// Same as readGmshMesh on an open stream; `name` is used in messages.
TetMesh readGmshMesh(std::istream& in, const std::string& name, MeshFileInfo* info = nullptr);

} // namespace softbody
