// Bodies of a mesh: cells that share a point belong to one body (connected component).
#pragma once

#include "softbody/common/geometry.h"

#include <cstdint>
#include <vector>

namespace softbody
{

struct Components
{
  std::vector<std::int32_t> ofCell; ///< component of each cell, numbered 0.. by first cell
  std::int32_t count = 0;
};

/// Connected components of cells given in CSR form (cell c has the points
/// cellPoints[cellOffsets[c] .. cellOffsets[c + 1])). Components are numbered in the order of
/// their first cell, so the numbering does not depend on anything but the cell order.
Components connectedComponents(std::size_t pointCount, const std::vector<std::int64_t>& cellOffsets,
  const std::vector<std::int64_t>& cellPoints);

/// The same for tets: the bodies a tet mesh's tets form.
Components tetComponents(std::size_t pointCount, const std::vector<Tet>& tets);

} // namespace softbody
