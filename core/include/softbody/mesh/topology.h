// Connectivity derived from the tets: unique edges and per-vertex incidence lists (CSR).
// The incidence lists drive "gather" loops: each vertex sums the contributions of its own
// edges and tets, so parallel loops never write to shared memory and the summation order is
// fixed, which makes results independent of the number of threads.
#pragma once

#include "softbody/common/geometry.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace softbody
{

struct Edge
{
  std::int32_t a; ///< smaller point index
  std::int32_t b; ///< larger point index
};

/// Compressed sparse rows: items of row i are items[offsets[i] .. offsets[i+1]).
struct Csr
{
  std::vector<std::int32_t> offsets;
  std::vector<std::int32_t> items;
  std::size_t rowCount() const { return offsets.empty() ? 0 : offsets.size() - 1; }
};

struct Topology
{
  std::size_t vertexCount = 0;
  std::vector<Tet> tets;
  std::vector<Edge> edges;  ///< unique, a < b, sorted lexicographically
  Csr vertexEdges;          ///< vertex -> indices into edges
  Csr vertexTetCorners;     ///< vertex -> 4 * tet + corner
  Csr tetEdges;             ///< tet -> its 6 edge indices (rows of 6)
};

/// Unique edges of a set of tets, sorted so the result does not depend on tet order details.
std::vector<Edge> extractUniqueEdges(const std::vector<Tet>& tets);

/// Builds a CSR from (row, item) pairs given in the order items should appear per row.
Csr buildCsr(std::size_t rowCount, const std::vector<std::int32_t>& rows,
  const std::vector<std::int32_t>& items);

Topology buildTopology(std::size_t vertexCount, std::vector<Tet> tets);

} // namespace softbody
