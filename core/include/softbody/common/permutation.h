// Storing arrays in another order: the one gather every reordering at set-up is built from
// (batches stored color by color or in interleaved streams, and the tests and benchmarks that
// store them as the solvers do).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

namespace softbody
{

/// v[s] = old v[order[s]]. An empty array (an optional per-item property) stays empty.
template <typename T>
void storeInOrder(std::vector<T>& v, const std::vector<std::int32_t>& order)
{
  if (v.empty())
  {
    return;
  }
  std::vector<T> sorted(order.size());
  for (std::size_t s = 0; s < order.size(); ++s)
  {
    sorted[s] = v[static_cast<std::size_t>(order[s])];
  }
  v = std::move(sorted);
}

} // namespace softbody
