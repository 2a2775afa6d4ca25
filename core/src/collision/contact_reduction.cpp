#include "softbody/collision/contact_reduction.h"

#include <algorithm>
#include <tuple>

namespace softbody
{

namespace
{

bool shareCorner(const std::array<std::int32_t, 3>& a, const std::array<std::int32_t, 3>& b)
{
  for (std::int32_t u : a)
  {
    for (std::int32_t v : b)
    {
      if (u >= 0 && u == v)
      {
        return true;
      }
    }
  }
  return false;
}

} // namespace

bool contactBefore(const Contact& x, const Contact& y)
{
  return std::tie(x.point, x.kind, x.source, x.other) < std::tie(y.point, y.kind, y.source, y.other);
}

void reduceCandidates(std::vector<ContactCandidate>& found, std::vector<std::uint32_t>& order,
  std::vector<std::uint32_t>& kept, ContactSet& out)
{
  if (found.size() == 1) // the common case: nothing to order or to merge
  {
    out.push_back(found[0].contact);
    return;
  }
  // Sorted through an index array: the candidates are large to move. Within a group (kind,
  // source): by distance, then by key, so every contact kept before one is no farther.
  auto group = [&](std::uint32_t x) { return std::tie(found[x].contact.kind, found[x].contact.source); };
  order.resize(found.size());
  for (std::uint32_t k = 0; k < order.size(); ++k)
  {
    order[k] = k;
  }
  std::sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) {
    if (group(x) != group(y))
    {
      return group(x) < group(y);
    }
    if (found[x].distance != found[y].distance)
    {
      return found[x].distance < found[y].distance;
    }
    return contactBefore(found[x].contact, found[y].contact);
  });
  kept.clear();
  for (std::size_t begin = 0; begin < order.size();)
  {
    std::size_t end = begin + 1;
    while (end < order.size() && group(order[end]) == group(order[begin]))
    {
      ++end;
    }
    const std::size_t groupStart = kept.size();
    bool behindKept = false; // the nearest face the point started behind: the one it leaves by
    for (std::size_t k = begin; k < end && kept.size() - groupStart < kMostContactsPerSource; ++k)
    {
      const ContactCandidate& c = found[order[k]];
      // Faces the point crossed in this substep are all kept: a fast point through a thin wall
      // is behind the face it crossed and behind the wall's far face, nearer, which it started
      // behind; the response keeps it on the side it started (mass-spring ignores the far face).
      if (c.behind && c.startedBehind)
      {
        if (behindKept)
        {
          continue; // a farther face behind the point: the other side of the body
        }
        behindKept = true;
      }
      bool covered = false;
      if (!c.onFace && c.contact.kind != ContactKind::PointPoint)
      {
        for (std::size_t q = groupStart; q < kept.size() && !covered; ++q)
        {
          covered = shareCorner(found[kept[q]].corners, c.corners); // kept ones are no farther
        }
      }
      if (!covered)
      {
        kept.push_back(order[k]);
      }
    }
    begin = end;
  }
  // Out in the ContactSet order.
  std::sort(kept.begin(), kept.end(), [&](std::uint32_t x, std::uint32_t y) {
    return contactBefore(found[x].contact, found[y].contact);
  });
  for (std::uint32_t k : kept)
  {
    out.push_back(found[k].contact);
  }
}

} // namespace softbody
