#include "softbody/collision/point_octree.h"

#include "softbody/common/parallel.h"
#include "softbody/common/morton.h"

#include <algorithm>
#include <numeric>

namespace softbody
{

namespace
{

constexpr int kBitsPerAxis = 21; // 63-bit codes

} // namespace

void PointOctree::build(const std::vector<Vec3>& positions, const std::vector<double>& reaches)
{
  const std::size_t n = positions.size();
  Nodes.clear();
  Codes.assign(n, 0);
  Items.resize(n);
  if (n == 0)
  {
    SortedPositions.clear();
    SortedReaches.clear();
    return;
  }
  Aabb bounds;
  for (const Vec3& p : positions)
  {
    bounds.grow(p);
  }
  const double extent = std::max((bounds.hi - bounds.lo).maxCoeff(), 1e-300);
  const double scale = static_cast<double>((1u << kBitsPerAxis) - 1) / extent;
  std::vector<std::uint64_t> code(n);
  parallelFor(n, 4096, [&](std::size_t i) {
    const Vec3 q = (positions[i] - bounds.lo) * scale;
    code[i] = spreadBits(static_cast<std::uint64_t>(q.x())) | spreadBits(static_cast<std::uint64_t>(q.y())) << 1 |
      spreadBits(static_cast<std::uint64_t>(q.z())) << 2;
  });
  std::iota(Items.begin(), Items.end(), 0);
  std::sort(Items.begin(), Items.end(), [&](std::int32_t a, std::int32_t b) {
    return code[a] != code[b] ? code[a] < code[b] : a < b;
  });
  SortedPositions.resize(n);
  SortedReaches.resize(n);
  parallelFor(n, 4096, [&](std::size_t s) {
    Codes[s] = code[Items[s]];
    SortedPositions[s] = positions[Items[s]];
    SortedReaches[s] = reaches[Items[s]];
  });
  Nodes.reserve(2 * n / kLeafSize + 16);
  Nodes.emplace_back();
  buildNode(0, 0, static_cast<std::uint32_t>(n), kBitsPerAxis);
}

void PointOctree::buildNode(std::uint32_t index, std::uint32_t begin, std::uint32_t end, int level)
{
  Nodes[index].begin = begin;
  Nodes[index].end = end;
  // Levels where every point of the range has the same next digit add nothing: skip them.
  auto digit = [&](std::uint32_t s, int atLevel) { return (Codes[s] >> (3 * (atLevel - 1))) & 7u; };
  while (level > 0 && digit(begin, level) == digit(end - 1, level))
  {
    --level;
  }
  if (end - begin <= kLeafSize || level == 0)
  {
    Aabb box;
    double maxReach = 0.0;
    for (std::uint32_t s = begin; s < end; ++s)
    {
      box.grow(SortedPositions[s]);
      maxReach = std::max(maxReach, SortedReaches[s]);
    }
    Nodes[index].box = box;
    Nodes[index].maxReach = maxReach;
    return;
  }
  // Children: the runs of equal digits (the codes are sorted, so the digit only grows).
  std::uint32_t bounds[9];
  std::uint32_t count = 0;
  bounds[0] = begin;
  for (std::uint32_t s = begin + 1; s < end; ++s)
  {
    if (digit(s, level) != digit(s - 1, level))
    {
      bounds[++count] = s;
    }
  }
  bounds[++count] = end;
  const auto first = static_cast<std::uint32_t>(Nodes.size());
  Nodes[index].firstChild = first;
  Nodes[index].childCount = count;
  Nodes.resize(Nodes.size() + count); // references into Nodes are invalid from here on
  Aabb box;
  double maxReach = 0.0;
  for (std::uint32_t c = 0; c < count; ++c)
  {
    buildNode(first + c, bounds[c], bounds[c + 1], level - 1);
    box.grow(Nodes[first + c].box);
    maxReach = std::max(maxReach, Nodes[first + c].maxReach);
  }
  Nodes[index].box = box;
  Nodes[index].maxReach = maxReach;
}

} // namespace softbody
