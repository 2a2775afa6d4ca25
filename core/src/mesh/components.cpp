#include "softbody/mesh/components.h"

#include "softbody/common/errors.h"

#include <numeric>

namespace softbody
{
namespace
{
/// Union-find over points with path halving; the root of a set is its smallest point.
struct DisjointSets
{
  std::vector<std::int64_t> parent;

  explicit DisjointSets(std::size_t n)
    : parent(n)
  {
    std::iota(parent.begin(), parent.end(), std::int64_t(0));
  }
  std::int64_t find(std::int64_t x)
  {
    while (parent[static_cast<std::size_t>(x)] != x)
    {
      auto& p = parent[static_cast<std::size_t>(x)];
      p = parent[static_cast<std::size_t>(p)];
      x = p;
    }
    return x;
  }
  void join(std::int64_t a, std::int64_t b)
  {
    a = find(a);
    b = find(b);
    if (a != b)
    {
      parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
    }
  }
};
} // namespace

Components connectedComponents(std::size_t pointCount, const std::vector<std::int64_t>& cellOffsets,
  const std::vector<std::int64_t>& cellPoints)
{
  Components result;
  if (cellOffsets.empty())
  {
    return result;
  }
  const std::size_t cells = cellOffsets.size() - 1;
  DisjointSets sets(pointCount);
  for (std::size_t c = 0; c < cells; ++c)
  {
    for (std::int64_t k = cellOffsets[c]; k < cellOffsets[c + 1]; ++k)
    {
      const std::int64_t p = cellPoints[static_cast<std::size_t>(k)];
      if (p < 0 || static_cast<std::size_t>(p) >= pointCount)
      {
        throw InvalidInputError("Cell " + std::to_string(c) + " refers to point " +
          std::to_string(p) + ", but the mesh has " + std::to_string(pointCount) + " points.");
      }
      if (k > cellOffsets[c])
      {
        sets.join(cellPoints[static_cast<std::size_t>(cellOffsets[c])], p);
      }
    }
  }
  std::vector<std::int32_t> numberOfRoot(pointCount, -1);
  result.ofCell.assign(cells, -1);
  for (std::size_t c = 0; c < cells; ++c)
  {
    if (cellOffsets[c] == cellOffsets[c + 1])
    {
      result.ofCell[c] = result.count++; // a cell without points is a body of its own
      continue;
    }
    const auto root = static_cast<std::size_t>(sets.find(cellPoints[static_cast<std::size_t>(cellOffsets[c])]));
    if (numberOfRoot[root] < 0)
    {
      numberOfRoot[root] = result.count++;
    }
    result.ofCell[c] = numberOfRoot[root];
  }
  return result;
}

Components tetComponents(std::size_t pointCount, const std::vector<Tet>& tets)
{
  std::vector<std::int64_t> offsets(tets.size() + 1), cellPoints;
  cellPoints.reserve(4 * tets.size());
  for (std::size_t t = 0; t < tets.size(); ++t)
  {
    offsets[t] = static_cast<std::int64_t>(4 * t);
    cellPoints.insert(cellPoints.end(), tets[t].begin(), tets[t].end());
  }
  offsets.back() = static_cast<std::int64_t>(cellPoints.size());
  return connectedComponents(pointCount, offsets, cellPoints);
}

} // namespace softbody
