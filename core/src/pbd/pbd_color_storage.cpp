// PbdSimulation: the parallel solver's color-sorted storage of its batches, and the lookups
// that map input links and tets onto it.
#include "softbody/pbd/pbd_simulation.h"

#include "softbody/common/parallel.h"
#include "softbody/common/stepping.h"
#include "softbody/pbd/pbd_solvers.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace softbody
{

namespace
{
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

/// Composes a batch's input -> storage map with a further reordering of its storage.
void composeSlots(std::vector<std::int32_t>& slot, const std::vector<std::int32_t>& order)
{
  const std::vector<std::int32_t> moved = slotsOf(order);
  if (slot.empty())
  {
    slot = moved;
    return;
  }
  for (std::int32_t& s : slot)
  {
    s = moved[static_cast<std::size_t>(s)];
  }
}
} // namespace

void PbdSimulation::storeLinksInOrder(const std::vector<std::int32_t>& order)
{
  Links.storeInOrder(order);
  composeSlots(LinkSlot, order);
  // TetEdges items name links by storage index.
  const std::vector<std::int32_t> moved = slotsOf(order);
  for (std::int32_t& item : TetEdges.items)
  {
    item = moved[static_cast<std::size_t>(item)];
  }
}

void PbdSimulation::storeVolumesInOrder(const std::vector<std::int32_t>& order)
{
  Volumes.storeInOrder(order);
  TetElastic.storeInOrder(order); // a continuum body's tets, in the same order
  composeSlots(VolumeSlot, order);
  if (TetEdges.rowCount() > 0)
  {
    // TetEdges rows follow the tets' storage order.
    Csr sorted;
    sorted.offsets.push_back(0);
    for (std::int32_t previous : order)
    {
      for (std::int32_t k = TetEdges.offsets[static_cast<std::size_t>(previous)];
           k < TetEdges.offsets[static_cast<std::size_t>(previous) + 1]; ++k)
      {
        sorted.items.push_back(TetEdges.items[static_cast<std::size_t>(k)]);
      }
      sorted.offsets.push_back(static_cast<std::int32_t>(sorted.items.size()));
    }
    TetEdges = std::move(sorted);
  }
}

void PbdSimulation::storeLinksAndVolumesByColor()
{
  // A color holds about one constraint in twenty: visited through an index list, every
  // projection would pull whole cache lines of constraint data for one constraint, so each
  // color would stream the batch from memory again. Stored color by color, a sweep streams it
  // once. Outputs map back through LinkSlot / VolumeSlot.
  storeLinksInOrder(LinkSchedule.coloring.order);
  storeVolumesInOrder(VolumeSchedule.coloring.order);
  for (BatchSchedule* schedule : { &LinkSchedule, &VolumeSchedule })
  {
    std::iota(schedule->coloring.order.begin(), schedule->coloring.order.end(), 0);
    schedule->storedByColor = true;
  }
}

void PbdSimulation::storeLinksAndVolumesInStreams()
{
  // Sequential Gauss-Seidel applies each projection before the next one reads the positions.
  // Stored sorted by vertex, consecutive constraints share particles, so every projection
  // would wait for the previous one's square root, divisions and stores: on the 180k-tet TetGen
  // ellipsoid an iteration takes 7.4-9.0 ms that way (15 ns per link, 21-30 ns per tet at 1
  // thread).
  // Stored as interleavedStreams (pbd_solvers.h), consecutive projections lie in distant parts
  // of the body and rarely share a particle, so the core overlaps up to four of them, while
  // each part still walks its region in vertex order (cache). Measured on that mesh, per
  // iteration: 2 parts 5.3 ms, 3 parts 4.4, 4 parts 4.2, 8 parts 4.1 (color order, without
  // locality, 4.1-4.5). Still one projection at a time in one fixed order, Gauss-Seidel; the
  // iterate (and the state hashes) of Gauss-Seidel bodies depend on that order, so they differ
  // from those of a vertex-sorted store.
  storeLinksInOrder(interleavedStreams(Links.size()));
  storeVolumesInOrder(interleavedStreams(Volumes.size()));
  // Blocks of four consecutive constraints then come from four parts of the body and almost
  // never share a particle: those are projected as one block of lanes (pbd_wide_kernels.h),
  // with the same result bit for bit.
  LinkSchedule.independentBlocks = independentBlocks(Links);
  VolumeSchedule.independentBlocks = independentBlocks(Volumes);
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
