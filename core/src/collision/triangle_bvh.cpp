#include "softbody/collision/triangle_bvh.h"

#include "softbody/common/parallel.h"

#include <algorithm>
#include <numeric>

namespace softbody
{

void TriangleBvh::build(const std::vector<Aabb>& boxes)
{
  const auto n = static_cast<std::uint32_t>(boxes.size());
  Items.resize(n);
  std::iota(Items.begin(), Items.end(), 0);
  Nodes.clear();
  ItemBoxes.clear();
  if (n == 0)
  {
    return;
  }
  Nodes.reserve(2 * (n / kLeafSize + 1));
  Nodes.emplace_back();
  buildNode(0, 0, n, boxes);
  refit(boxes);
}

void TriangleBvh::buildNode(std::uint32_t index, std::uint32_t begin, std::uint32_t end, const std::vector<Aabb>& boxes)
{
  Nodes[index].begin = begin;
  Nodes[index].end = end;
  if (end - begin <= kLeafSize)
  {
    return;
  }
  Aabb centres;
  for (std::uint32_t s = begin; s < end; ++s)
  {
    centres.grow(0.5 * (boxes[Items[s]].lo + boxes[Items[s]].hi));
  }
  int axis = 0;
  (centres.hi - centres.lo).maxCoeff(&axis);
  // Median split, ties broken by index so the tree does not depend on the sort's internals.
  const std::uint32_t middle = begin + (end - begin) / 2;
  auto centre = [&](std::int32_t item) { return boxes[item].lo[axis] + boxes[item].hi[axis]; };
  std::nth_element(Items.begin() + begin, Items.begin() + middle, Items.begin() + end,
    [&](std::int32_t a, std::int32_t b) { return centre(a) != centre(b) ? centre(a) < centre(b) : a < b; });
  const auto left = static_cast<std::uint32_t>(Nodes.size());
  Nodes[index].left = left;
  Nodes.resize(Nodes.size() + 2); // references into Nodes are invalid from here on
  buildNode(left, begin, middle, boxes);
  buildNode(left + 1, middle, end, boxes);
}

std::vector<std::uint32_t> TriangleBvh::groups(std::uint32_t maxItems) const
{
  std::vector<std::uint32_t> found;
  if (Nodes.empty())
  {
    return found;
  }
  std::vector<std::uint32_t> stack{ 0 };
  while (!stack.empty())
  {
    const std::uint32_t index = stack.back();
    stack.pop_back();
    const Node& node = Nodes[index];
    if (node.left == 0 || node.end - node.begin <= maxItems)
    {
      found.push_back(index);
      continue;
    }
    stack.push_back(node.left + 1);
    stack.push_back(node.left);
  }
  return found;
}

void TriangleBvh::refit(const std::vector<Aabb>& boxes)
{
  ItemBoxes.resize(Items.size());
  parallelFor(Items.size(), 4096, [&](std::size_t s) { ItemBoxes[s] = boxes[Items[s]]; });
  // Children come after their parents, so a backward pass sees children first. Sequential: one
  // union per node, a small part of a detection next to the queries.
  for (std::size_t i = Nodes.size(); i-- > 0;)
  {
    Node& node = Nodes[i];
    if (node.left == 0)
    {
      Aabb box;
      for (std::uint32_t s = node.begin; s < node.end; ++s)
      {
        box.grow(ItemBoxes[s]);
      }
      node.box = box;
    }
    else
    {
      node.box = Nodes[node.left].box;
      node.box.grow(Nodes[node.left + 1].box);
    }
  }
}

} // namespace softbody
