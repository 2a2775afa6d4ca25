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

Coloring colorConstraints(std::size_t particleCount, const std::vector<std::int32_t>& particles,
  int arity, const std::vector<char>& movable)
{
  const std::size_t count = particles.size() / static_cast<std::size_t>(arity);
  const Csr slots = particleSlots(particleCount, particles);
  std::vector<std::int32_t> color(count, -1);
  // forbidden[k] == c means color k is taken by a neighbor of constraint c; stamping avoids
  // clearing the array for every constraint.
  std::vector<std::int64_t> forbidden;
  std::int32_t colors = 0;
  for (std::size_t c = 0; c < count; ++c)
  {
    for (int k = 0; k < arity; ++k)
    {
      const std::int32_t p = particles[c * static_cast<std::size_t>(arity) + static_cast<std::size_t>(k)];
      if (!movable.empty() && !movable[static_cast<std::size_t>(p)])
      {
        continue;
      }
      for (std::int32_t s = slots.offsets[static_cast<std::size_t>(p)];
           s < slots.offsets[static_cast<std::size_t>(p) + 1]; ++s)
      {
        const std::int32_t other = color[static_cast<std::size_t>(slots.items[static_cast<std::size_t>(s)] / arity)];
        if (other >= 0)
        {
          forbidden[static_cast<std::size_t>(other)] = static_cast<std::int64_t>(c);
        }
      }
    }
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

} // namespace softbody
