// What every reader fuzz target checks of a mesh a reader returned.
#pragma once

#include "softbody/mesh/tet_mesh.h"

#include <cstdint>
#include <cstdlib>

namespace softbody::fuzz
{

/// Aborts (a finding) when a tet names a point the mesh does not have: readers must check
/// every index they return. Repeated indices are allowed here; prepareTetMesh refuses them.
inline void abortOnIndexOutOfRange(const TetMesh& mesh)
{
  for (const Tet& tet : mesh.tets)
  {
    for (std::int32_t v : tet)
    {
      if (v < 0 || static_cast<std::size_t>(v) >= mesh.points.size())
      {
        std::abort();
      }
    }
  }
}

} // namespace softbody::fuzz
