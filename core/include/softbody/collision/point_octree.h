// The octree broad phase for points: the points sorted along a Morton (Z-order) curve, so every
// octree cell is a contiguous range of them, and the tree is built by splitting ranges on the
// next three bits of the codes. Each node keeps the tight box of its points and the largest
// reach among them, so a query descends only into nodes that can hold a partner: cells adapt
// to where points are, and a few large or fast points make only their own nodes wide (the
// uniform grid's cell must fit the largest reach everywhere).
#pragma once

#include "softbody/collision/aabb.h"

#include <cstdint>
#include <vector>

namespace softbody
{

class PointOctree
{
public:
  /// Leaves hold at most this many points (or all points of one finest cell).
  static constexpr std::uint32_t kLeafSize = 16;

  /// Builds the tree over items 0..n-1. Deterministic: points are ordered by (code, index).
  void build(const std::vector<Vec3>& positions, const std::vector<double>& reaches);

  /// visit(item) for every item j > `after` with |p - x_j| <= reach + reach_j, each once
  /// (-1: all items).
  template <typename Visit>
  void forEachNear(const Vec3& p, double reach, std::int32_t after, const Visit& visit) const;

  std::size_t nodeCount() const { return Nodes.size(); }

private:
  struct Node
  {
    Aabb box;                  ///< tight box of the node's points
    double maxReach = 0.0;     ///< largest reach among them
    std::uint32_t begin = 0;   ///< range of sorted points
    std::uint32_t end = 0;
    std::uint32_t firstChild = 0; ///< children are contiguous; 0 children = leaf
    std::uint32_t childCount = 0;
  };
  void buildNode(std::uint32_t index, std::uint32_t begin, std::uint32_t end, int level);

  std::vector<Node> Nodes;
  std::vector<std::uint64_t> Codes; ///< sorted Morton codes
  std::vector<std::int32_t> Items;  ///< items in code order
  std::vector<Vec3> SortedPositions;
  std::vector<double> SortedReaches;
};

template <typename Visit>
void PointOctree::forEachNear(const Vec3& p, double reach, std::int32_t after, const Visit& visit) const
{
  if (Nodes.empty())
  {
    return;
  }
  std::uint32_t stack[64 * 8];
  int top = 0;
  stack[top++] = 0;
  while (top > 0)
  {
    const Node& node = Nodes[stack[--top]];
    const double within = reach + node.maxReach;
    if (node.box.squaredDistance(p) > within * within)
    {
      continue;
    }
    if (node.childCount == 0)
    {
      for (std::uint32_t s = node.begin; s < node.end; ++s)
      {
        const double pair = reach + SortedReaches[s];
        if (Items[s] > after && (SortedPositions[s] - p).squaredNorm() <= pair * pair)
        {
          visit(Items[s]);
        }
      }
      continue;
    }
    for (std::uint32_t c = 0; c < node.childCount; ++c)
    {
      stack[top++] = node.firstChild + c;
    }
  }
}

} // namespace softbody
