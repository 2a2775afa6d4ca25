// The broad phase for triangles (obstacle surfaces and body surfaces): a bounding-volume
// hierarchy of axis-aligned boxes. The tree's shape is built once from the triangles' boxes
// (median split on the longest axis of their centres), and each detection only refits it:
// new leaf boxes, then every parent the union of its children. A deforming surface keeps its
// connectivity, so its tree stays valid; it only loosens when the surface moves far from
// where it was built (refit is O(n), a rebuild O(n log n)).
#pragma once

#include "softbody/collision/aabb.h"

#include <cstdint>
#include <span>
#include <vector>

namespace softbody
{

class TriangleBvh
{
public:
  static constexpr std::uint32_t kLeafSize = 4;

  /// The tree over items 0..n-1 with these boxes. Deterministic (no threads).
  void build(const std::vector<Aabb>& boxes);
  /// New boxes for the same items: same tree, parents refitted bottom-up.
  void refit(const std::vector<Aabb>& boxes);

  /// visit(item) for every item whose box is within `radius` of p.
  template <typename Visit>
  void forEachNear(const Vec3& p, double radius, const Visit& visit) const;

  /// visit(item) for every item whose box overlaps `box`.
  template <typename Visit>
  void forEachOverlapping(const Aabb& box, const Visit& visit) const;

  std::size_t itemCount() const { return Items.size(); }

  /// The highest nodes that hold at most `maxItems` items each, in depth-first order: groups
  /// of nearby items that together partition the items. The tree's shape is fixed at build, so
  /// the groups are too; a group can query another tree once with its node's box where each of
  /// its items would otherwise query it alone.
  std::vector<std::uint32_t> groups(std::uint32_t maxItems) const;
  /// A node's box (as of the last refit) and its items (tree order).
  const Aabb& nodeBox(std::uint32_t node) const { return Nodes[node].box; }
  std::span<const std::int32_t> nodeItems(std::uint32_t node) const
  {
    return { Items.data() + Nodes[node].begin, Nodes[node].end - Nodes[node].begin };
  }

private:
  struct Node
  {
    Aabb box;
    std::uint32_t begin = 0; ///< leaf: its items are Items[begin, end)
    std::uint32_t end = 0;
    std::uint32_t left = 0;  ///< 0 = leaf (the root is never a child); right = left + 1
  };
  void buildNode(std::uint32_t index, std::uint32_t begin, std::uint32_t end, const std::vector<Aabb>& boxes);

  std::vector<Node> Nodes; ///< parents before children: refit runs backwards
  std::vector<std::int32_t> Items;
  std::vector<Aabb> ItemBoxes; ///< in Items order
};

template <typename Visit>
void TriangleBvh::forEachNear(const Vec3& p, double radius, const Visit& visit) const
{
  if (Nodes.empty())
  {
    return;
  }
  const double radius2 = radius * radius;
  std::uint32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0)
  {
    const Node& node = Nodes[stack[--top]];
    if (node.box.squaredDistance(p) > radius2)
    {
      continue;
    }
    if (node.left == 0)
    {
      for (std::uint32_t s = node.begin; s < node.end; ++s)
      {
        if (ItemBoxes[s].squaredDistance(p) <= radius2)
        {
          visit(Items[s]);
        }
      }
      continue;
    }
    stack[top++] = node.left + 1;
    stack[top++] = node.left;
  }
}

template <typename Visit>
void TriangleBvh::forEachOverlapping(const Aabb& box, const Visit& visit) const
{
  if (Nodes.empty())
  {
    return;
  }
  std::uint32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0)
  {
    const Node& node = Nodes[stack[--top]];
    if (!node.box.overlaps(box))
    {
      continue;
    }
    if (node.left == 0)
    {
      for (std::uint32_t s = node.begin; s < node.end; ++s)
      {
        if (ItemBoxes[s].overlaps(box))
        {
          visit(Items[s]);
        }
      }
      continue;
    }
    stack[top++] = node.left + 1;
    stack[top++] = node.left;
  }
}

} // namespace softbody
