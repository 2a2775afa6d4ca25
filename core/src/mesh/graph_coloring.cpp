#include "softbody/mesh/graph_coloring.h"

#include <algorithm>

namespace softbody
{

Csr particleSlots(std::size_t particleCount, const std::vector<std::int32_t>& particles)
{
  std::vector<std::int32_t> rows(particles.begin(), particles.end());
  std::vector<std::int32_t> items(particles.size());
  for (std::size_t s = 0; s < items.size(); ++s)
  {
    items[s] = static_cast<std::int32_t>(s);
  }
  return buildCsr(particleCount, rows, items);
}

namespace
{

/// Greedy coloring of items 0..count-1 in index order: each takes the smallest color none of
/// its earlier-colored neighbours has. forEachNeighbour(c, visit) visits c's neighbours (an
/// uncolored one, or c itself, is ignored).
template <class ForEachNeighbour>
Coloring greedyColoring(std::size_t count, const ForEachNeighbour& forEachNeighbour)
{
  std::vector<std::int32_t> color(count, -1);
  // forbidden[k] == c means color k is taken by a neighbor of item c; stamping avoids
  // clearing the array for every item.
  std::vector<std::int64_t> forbidden;
  std::int32_t colors = 0;
  for (std::size_t c = 0; c < count; ++c)
  {
    forEachNeighbour(c, [&](std::size_t neighbour) {
      const std::int32_t other = color[neighbour];
      if (other >= 0 && neighbour != c)
      {
        forbidden[static_cast<std::size_t>(other)] = static_cast<std::int64_t>(c);
      }
    });
    std::int32_t chosen = 0;
    while (chosen < colors && forbidden[static_cast<std::size_t>(chosen)] == static_cast<std::int64_t>(c))
    {
      ++chosen;
    }
    if (chosen == colors)
    {
      ++colors;
      forbidden.push_back(-1);
    }
    color[c] = chosen;
  }

  Coloring result;
  result.colorOffsets.assign(static_cast<std::size_t>(colors) + 1, 0);
  for (std::int32_t k : color)
  {
    ++result.colorOffsets[static_cast<std::size_t>(k) + 1];
  }
  for (std::size_t k = 1; k < result.colorOffsets.size(); ++k)
  {
    result.colorOffsets[k] += result.colorOffsets[k - 1];
  }
  result.order.resize(count);
  std::vector<std::int32_t> next(result.colorOffsets.begin(), result.colorOffsets.end() - 1);
  for (std::size_t c = 0; c < count; ++c)
  {
    result.order[static_cast<std::size_t>(next[static_cast<std::size_t>(color[c])]++)] =
      static_cast<std::int32_t>(c);
  }
  return result;
}

} // namespace

Coloring colorConstraints(std::size_t particleCount, const std::vector<std::int32_t>& particles,
  int arity, const std::vector<char>& movable)
{
  const auto width = static_cast<std::size_t>(arity);
  const Csr slots = particleSlots(particleCount, particles);
  return greedyColoring(particles.size() / width, [&](std::size_t c, const auto& visit) {
    for (std::size_t k = 0; k < width; ++k)
    {
      const auto p = static_cast<std::size_t>(particles[c * width + k]);
      if (!movable.empty() && !movable[p])
      {
        continue;
      }
      for (std::int32_t s = slots.offsets[p]; s < slots.offsets[p + 1]; ++s)
      {
        visit(static_cast<std::size_t>(slots.items[static_cast<std::size_t>(s)]) / width);
      }
    }
  });
}

Coloring colorVertices(const Topology& topology)
{
  return greedyColoring(topology.vertexCount, [&](std::size_t v, const auto& visit) {
    for (std::int32_t s = topology.vertexEdges.offsets[v]; s < topology.vertexEdges.offsets[v + 1]; ++s)
    {
      const Edge& edge = topology.edges[static_cast<std::size_t>(topology.vertexEdges.items[static_cast<std::size_t>(s)])];
      visit(static_cast<std::size_t>(edge.a == static_cast<std::int32_t>(v) ? edge.b : edge.a));
    }
  });
}

} // namespace softbody
