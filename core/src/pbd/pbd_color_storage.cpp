// PbdSimulation: the parallel solver's color-sorted storage of its batches, and the lookups
// that map input links and tets onto it.
#include "softbody/pbd/pbd_simulation.h"

#include "softbody/common/parallel.h"
#include "softbody/common/stepping.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace softbody
{

namespace
{
/// v[s] = old v[order[s]]: stores a batch array in the given order.
template <typename T>
void permute(std::vector<T>& v, const std::vector<std::int32_t>& order)
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

/// The inverse of an order: slot[original] = storage index.
std::vector<std::int32_t> slotsOf(const std::vector<std::int32_t>& order)
{
  std::vector<std::int32_t> slot(order.size());
  for (std::size_t s = 0; s < order.size(); ++s)
  {
    slot[static_cast<std::size_t>(order[s])] = static_cast<std::int32_t>(s);
  }
  return slot;
}
} // namespace

void PbdSimulation::storeLinksAndVolumesByColor()
{
  // A color holds about one constraint in twenty: visited through an index list, every
  // projection would pull whole cache lines of constraint data for one constraint, so each
  // color would stream the batch from memory again. Stored color by color, a sweep streams it
  // once. Outputs map back through LinkSlot / VolumeSlot.
  const std::vector<std::int32_t> linkOrder = LinkSchedule.coloring.order;
  permute(Links.ends, linkOrder);
  permute(Links.originalRest, linkOrder);
  permute(Links.rest, linkOrder);
  permute(Links.stiffnessScale, linkOrder);
  permute(Links.compliance, linkOrder);
  permute(Links.broken, linkOrder);
  LinkSlot = slotsOf(linkOrder);
  const std::vector<std::int32_t> tetOrder = VolumeSchedule.coloring.order;
  permute(Volumes.tets, tetOrder);
  permute(Volumes.restVolume, tetOrder);
  permute(Volumes.compliance, tetOrder);
  permute(Volumes.broken, tetOrder);
  VolumeSlot = slotsOf(tetOrder);
  for (BatchSchedule* schedule : { &LinkSchedule, &VolumeSchedule })
  {
    std::iota(schedule->coloring.order.begin(), schedule->coloring.order.end(), 0);
  }
  if (TetEdges.rowCount() > 0)
  {
    // Rows follow the tets' new order; items name the links' new slots.
    Csr sorted;
    sorted.offsets.push_back(0);
    for (std::int32_t original : tetOrder)
    {
      for (std::int32_t k = TetEdges.offsets[static_cast<std::size_t>(original)];
           k < TetEdges.offsets[static_cast<std::size_t>(original) + 1]; ++k)
      {
        sorted.items.push_back(LinkSlot[static_cast<std::size_t>(TetEdges.items[static_cast<std::size_t>(k)])]);
      }
      sorted.offsets.push_back(static_cast<std::int32_t>(sorted.items.size()));
    }
    TetEdges = std::move(sorted);
  }
}

bool PbdSimulation::linkBroken(std::size_t link) const
{
  return Links.broken[LinkSlot.empty() ? link : static_cast<std::size_t>(LinkSlot[link])] != 0;
}

bool PbdSimulation::tetBroken(std::size_t tet) const
{
  return Volumes.broken[VolumeSlot.empty() ? tet : static_cast<std::size_t>(VolumeSlot[tet])] != 0;
}

} // namespace softbody
