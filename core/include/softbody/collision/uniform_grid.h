// The uniform-grid broad phase for points: a counting-sort grid (Teschner et al. 2003,
// "Optimized Spatial Hashing for Collision Detection of Deformable Objects"; Green 2008,
// "Particle Simulation using CUDA"). Each point's cell gets a bucket, the points are
// counting-sorted by bucket (histogram, prefix sums, scatter), and what a query reads
// (position, reach, index) is copied into that order, so a query reads contiguous memory.
//
// Buckets: where the points' bounding box has few enough cells (at most kDenseCellsPerPoint
// per point), the bucket is the cell's linear index in the box: no two cells share a bucket.
// Otherwise (points spread far apart) the cell is hashed, bucket = (ix + H(iy, iz)) mod size,
// which still keeps consecutive x cells in consecutive buckets. Either way a query reads the
// 3 x 3 x 3 neighbourhood as 9 runs of 3 buckets: 9 ranges of the sorted entries rather than 27
// lookups. Cells sharing a hash bucket only add candidates the distance test rejects; a bucket
// two runs share is read once, so no point is visited twice.
#pragma once

#include "softbody/common/geometry.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace softbody
{

class UniformGrid
{
public:
  /// The dense layout is used up to this many cells per point (the prefix sums cost 4 bytes
  /// per cell).
  static constexpr std::uint64_t kDenseCellsPerPoint = 8;

  /// Sorts items 0..n-1 (positions, reaches) into cells of `cellSize`, which must be at least
  /// twice the largest reach so that every pair within reach_i + reach_j is in neighbouring
  /// cells. Deterministic: the sort is stable, items of one bucket stay in index order.
  /// `groups` (empty, or one per item): forEachPairFrom skips pairs of one group, before their
  /// distance test; the group is stored beside the sorted entries, so the test reads contiguous
  /// memory (the collision detector's bodies: without self collision most pairs the grid finds
  /// are neighbours in one body, and looking their bodies up item by item would be a quarter of the
  /// detection on 100,000 particles).
  void build(const std::vector<Vec3>& positions, const std::vector<double>& reaches, double cellSize,
    const std::vector<std::int32_t>& groups = {});

  /// visit(item) for every item j > `after` with |p - x_j| <= reach + reach_j, each once (pass
  /// -1 for all items; a point querying with its own index finds each pair once). A few
  /// farther items may be visited too (reaches are stored in single precision, rounded up):
  /// the caller's exact test decides.
  template <typename Visit>
  void forEachNear(const Vec3& p, double reach, std::int32_t after, const Visit& visit) const;

  /// Every pair of items within reach_i + reach_j (of different groups, when built with groups),
  /// each exactly once over all sorted entries
  /// 0..entryCount()-1: entry s calls visitPair(a, b), a < b, for the pairs it owns. A few
  /// farther pairs may come too (reaches in single precision, rounded up). Dense layout: a half
  /// stencil - the rest of the entry's own cell and the 13 neighbour cells after it in the
  /// sorted order (4.5 runs instead of 9, and no index test); the other 13 find the pair from
  /// their side. Hashed layout: forEachNear with the entry's item as `after`.
  std::size_t entryCount() const { return Entries.size(); }
  template <typename VisitPair>
  void forEachPairFrom(std::size_t entry, const VisitPair& visitPair) const;

  bool dense() const { return Dense; }

private:
  std::int64_t cellOf(double coordinate) const
  {
    const double scaled = coordinate * InverseCell;
    const auto cell = static_cast<std::int64_t>(scaled); // truncates toward zero: floor below
    return cell - (scaled < static_cast<double>(cell) ? 1 : 0);
  }
  std::uint64_t hashedBucket(std::int64_t ix, std::int64_t iy, std::int64_t iz) const
  {
    const std::uint64_t row = static_cast<std::uint64_t>(iy) * 73856093ull ^ static_cast<std::uint64_t>(iz) * 19349663ull;
    return (static_cast<std::uint64_t>(ix) + row) & Mask;
  }
  template <typename Scan>
  void scanDense(std::int64_t ix, std::int64_t iy, std::int64_t iz, const Scan& scan) const;
  template <typename Scan>
  void scanHashed(std::int64_t ix, std::int64_t iy, std::int64_t iz, const Scan& scan) const;
  /// visitEntry(s) for every sorted entry s with item > `after` within reach of p.
  template <typename VisitEntry>
  void forEachEntryNear(const Vec3& p, double reach, std::int32_t after, const VisitEntry& visitEntry) const;

  /// One sorted item: what a query reads, in 32 bytes (two per cache line).
  struct Entry
  {
    Vec3 position;
    float reach = 0.0f; ///< rounded up to single precision (a conservative filter)
    std::int32_t item = 0;
  };

  double InverseCell = 1.0;
  bool Dense = false;
  std::int64_t Origin[3] = { 0, 0, 0 }; ///< dense: the box's first cell
  std::int64_t Cells[3] = { 0, 0, 0 };  ///< dense: cells per axis
  std::uint64_t Mask = 0;               ///< hashed: table size - 1
  std::vector<std::uint32_t> BucketStart; ///< prefix sums: bucket b holds [start[b], start[b+1])
  std::vector<Entry> Entries;             ///< items sorted by bucket (stable: ascending in each)
  std::vector<std::int32_t> EntryGroups;  ///< the entries' groups (empty: built without groups)
  std::vector<std::int64_t> ScratchCells;
  std::vector<std::uint32_t> ScratchBuckets;
  std::vector<std::int32_t> ScratchItems;
  std::vector<std::uint32_t> ScratchNext;
};

template <typename Scan>
void UniformGrid::scanDense(std::int64_t ix, std::int64_t iy, std::int64_t iz, const Scan& scan) const
{
  // Cells outside the box hold nothing: clamp the runs, skip the rows.
  const std::int64_t x0 = std::max<std::int64_t>(ix - 1 - Origin[0], 0);
  const std::int64_t x1 = std::min<std::int64_t>(ix + 1 - Origin[0], Cells[0] - 1);
  if (x0 > x1)
  {
    return;
  }
  for (std::int64_t z = iz - 1 - Origin[2]; z <= iz + 1 - Origin[2]; ++z)
  {
    if (z < 0 || z >= Cells[2])
    {
      continue;
    }
    for (std::int64_t y = iy - 1 - Origin[1]; y <= iy + 1 - Origin[1]; ++y)
    {
      if (y < 0 || y >= Cells[1])
      {
        continue;
      }
      const auto row = static_cast<std::uint64_t>((z * Cells[1] + y) * Cells[0]);
      scan(BucketStart[row + static_cast<std::uint64_t>(x0)], BucketStart[row + static_cast<std::uint64_t>(x1) + 1]);
    }
  }
}

template <typename Scan>
void UniformGrid::scanHashed(std::int64_t ix, std::int64_t iy, std::int64_t iz, const Scan& scan) const
{
  // Two runs share a bucket only when their starts are less than 3 apart (modulo the table):
  // rare, so each run is compared with the earlier ones and read as one range unless it
  // clashes or wraps; then bucket by bucket, skipping those an earlier run already read.
  // (Sorting the 9 runs instead takes about a quarter of the samples in a profile of the
  // detection on 100,000 particles.)
  const std::uint64_t size = Mask + 1;
  std::uint64_t first[9];
  int runs = 0;
  for (std::int64_t dz = -1; dz <= 1; ++dz)
  {
    for (std::int64_t dy = -1; dy <= 1; ++dy)
    {
      const std::uint64_t start = hashedBucket(ix - 1, iy + dy, iz + dz);
      bool clash = start + 3 > size;
      for (int q = 0; q < runs; ++q)
      {
        const std::uint64_t apart = (start - first[q]) & Mask;
        clash = clash || apart < 3 || apart > size - 3;
      }
      if (!clash)
      {
        scan(BucketStart[start], BucketStart[start + 3]);
      }
      else
      {
        for (std::uint64_t t = 0; t < 3; ++t)
        {
          const std::uint64_t bucket = (start + t) & Mask;
          bool seen = false;
          for (int q = 0; q < runs; ++q)
          {
            seen = seen || ((bucket - first[q]) & Mask) < 3;
          }
          if (!seen)
          {
            scan(BucketStart[bucket], BucketStart[bucket + 1]);
          }
        }
      }
      first[runs++] = start;
    }
  }
}

template <typename VisitEntry>
void UniformGrid::forEachEntryNear(const Vec3& p, double reach, std::int32_t after, const VisitEntry& visitEntry) const
{
  if (Entries.empty())
  {
    return;
  }
  auto scan = [&](std::uint32_t s, std::uint32_t e) {
    for (; s < e; ++s)
    {
      const Entry& entry = Entries[s];
      const double within = reach + static_cast<double>(entry.reach);
      if (entry.item > after && (entry.position - p).squaredNorm() <= within * within)
      {
        visitEntry(s);
      }
    }
  };
  const std::int64_t ix = cellOf(p.x()), iy = cellOf(p.y()), iz = cellOf(p.z());
  if (Dense)
  {
    scanDense(ix, iy, iz, scan);
  }
  else
  {
    scanHashed(ix, iy, iz, scan);
  }
}

template <typename Visit>
void UniformGrid::forEachNear(const Vec3& p, double reach, std::int32_t after, const Visit& visit) const
{
  forEachEntryNear(p, reach, after, [&](std::uint32_t s) { visit(Entries[s].item); });
}

template <typename VisitPair>
void UniformGrid::forEachPairFrom(std::size_t entry, const VisitPair& visitPair) const
{
  const Entry& self = Entries[entry];
  const double reach = static_cast<double>(self.reach);
  const bool grouped = !EntryGroups.empty();
  const std::int32_t group = grouped ? EntryGroups[entry] : 0;
  if (!Dense)
  {
    forEachEntryNear(self.position, reach, self.item, [&](std::uint32_t s) {
      if (!grouped || EntryGroups[s] != group)
      {
        visitPair(self.item, Entries[s].item);
      }
    });
    return;
  }
  auto scan = [&](std::uint32_t s, std::uint32_t e) {
    for (; s < e; ++s)
    {
      if (grouped && EntryGroups[s] == group)
      {
        continue;
      }
      const Entry& other = Entries[s];
      const double within = reach + static_cast<double>(other.reach);
      if ((other.position - self.position).squaredNorm() <= within * within)
      {
        visitPair(std::min(self.item, other.item), std::max(self.item, other.item));
      }
    }
  };
  // The same cell the build computed (same position, same scale), in box coordinates.
  const std::int64_t x = cellOf(self.position.x()) - Origin[0];
  const std::int64_t y = cellOf(self.position.y()) - Origin[1];
  const std::int64_t z = cellOf(self.position.z()) - Origin[2];
  const std::int64_t x0 = std::max<std::int64_t>(x - 1, 0);
  const std::int64_t x1 = std::min<std::int64_t>(x + 1, Cells[0] - 1);
  auto rowStart = [&](std::int64_t zz, std::int64_t yy) {
    return static_cast<std::uint64_t>((zz * Cells[1] + yy) * Cells[0]);
  };
  // Own row: after this entry, through the next cell.
  scan(static_cast<std::uint32_t>(entry) + 1, BucketStart[rowStart(z, y) + static_cast<std::uint64_t>(x1) + 1]);
  // The next row of this layer, and the three rows of the next layer: whole runs of 3 cells.
  auto scanRow = [&](std::int64_t zz, std::int64_t yy) {
    if (zz < Cells[2] && yy >= 0 && yy < Cells[1])
    {
      const std::uint64_t row = rowStart(zz, yy);
      scan(BucketStart[row + static_cast<std::uint64_t>(x0)], BucketStart[row + static_cast<std::uint64_t>(x1) + 1]);
    }
  };
  scanRow(z, y + 1);
  for (std::int64_t dy = -1; dy <= 1; ++dy)
  {
    scanRow(z + 1, y + dy);
  }
}

} // namespace softbody
