// The connectivity every tet-based element family shares: the mesh edge between two corners of
// a tet, and the (tet, corner) pairs at a point in Topology::vertexTetCorners' order, the
// gather order that fixes each point's summation order.
#pragma once

#include "softbody/mesh/topology.h"

#include <cstddef>
#include <cstdint>

namespace softbody
{

/// The mesh edge between corners a and b (a != b) of tet t, from Topology::tetEdges.
inline std::int32_t tetEdgeBetween(const Topology& topology, std::size_t t, int a, int b)
{
  // Index into a tetEdges row of the edge between corners a and b, in the order of
  // topology.cpp's kTetEdgeCorners {01, 02, 03, 12, 13, 23}.
  constexpr int kLocalEdge[4][4] = { { -1, 0, 1, 2 }, { 0, -1, 3, 4 }, { 1, 3, -1, 5 },
    { 2, 4, 5, -1 } };
  return topology.tetEdges.items[6 * t + static_cast<std::size_t>(kLocalEdge[a][b])];
}

/// visit(tet, corner) for each tet corner at `vertex`, in Topology::vertexTetCorners' order.
template <class Visit>
void forEachTetCorner(const Topology& topology, std::int32_t vertex, Visit&& visit)
{
  const Csr& corners = topology.vertexTetCorners;
  for (std::int32_t k = corners.offsets[static_cast<std::size_t>(vertex)];
       k < corners.offsets[static_cast<std::size_t>(vertex) + 1]; ++k)
  {
    const std::int32_t item = corners.items[static_cast<std::size_t>(k)];
    visit(static_cast<std::size_t>(item / 4), static_cast<int>(item % 4));
  }
}

} // namespace softbody
