// The uniform-grid broad phase for points: a counting-sort grid (Teschner et al. 2003,
// "Optimized Spatial Hashing for Collision Detection of Deformable Objects"; Green 2008,
// "Particle Simulation using CUDA"). Each point's cell gets a bucket, the points are
// counting-sorted by bucket (histogram, prefix sums, scatter), and what a query reads
// (position, reach, group) is copied into that order, so a query reads contiguous memory.
//
// The filter a query runs on every sorted entry is in single precision, on coordinates
// relative to the points' box corner, with its reach widened by more than float rounding can
// move a distance (see filterSlack): a conservative filter that lets a few farther pairs
// through and never drops one within reach; the caller's exact test in double decides. Each
// test is branch-free (the hit is appended to a short buffer and the count advanced by 0 or 1):
// most entries a query reads are rejected, in no pattern a branch predictor learns.
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
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
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
  /// `groups` (empty, or one per item): forEachPairFrom skips pairs of one group, in the same
  /// branch-free test as the distance (the collision detector's bodies: without self collision
  /// most pairs the grid finds are neighbours in one body).
  void build(const std::vector<Vec3>& positions, const std::vector<double>& reaches, double cellSize,
    const std::vector<std::int32_t>& groups = {});

  /// visit(item) for every item j > `after` with |p - x_j| <= reach + reach_j, each once (pass
  /// -1 for all items; a point querying with its own index finds each pair once). A few
  /// farther items may be visited too (the filter is in single precision, widened): the
  /// caller's exact test decides.
  template <typename Visit>
  void forEachNear(const Vec3& p, double reach, std::int32_t after, const Visit& visit) const;

  /// Every pair of items within reach_i + reach_j (of different groups, when built with groups),
  /// each exactly once over all sorted entries
  /// 0..entryCount()-1: entry s calls visitPair(a, b), a < b, for the pairs it owns. A few
  /// farther pairs may come too (see forEachNear). Dense layout: a half
  /// stencil - the rest of the entry's own cell and the 13 neighbour cells after it in the
  /// sorted order (4.5 runs instead of 9, and no index test); the other 13 find the pair from
  /// their side. Hashed layout: forEachNear with the entry's item as `after`.
  std::size_t entryCount() const { return Positions.size(); }
  template <typename VisitPair>
  void forEachPairFrom(std::size_t entry, const VisitPair& visitPair) const;

  bool dense() const { return Dense; }

private:
  /// Reaches are widened by this factor and by filterSlack before the single-precision test:
  /// 16 times float's relative rounding, so no pair within reach is dropped.
  static constexpr float kReachGrowth = 1.0f + 0x1p-20f;
  /// Entries the filter tests at once.
  static constexpr std::uint32_t kLanes = 4;
  /// The group of a query point (forEachNear); build refuses it as an item's group.
  static constexpr std::int32_t kNoGroup = std::numeric_limits<std::int32_t>::min();

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
  /// A query's coordinates relative to the corner, in single precision.
  struct FloatPoint
  {
    float x, y, z;
  };
  FloatPoint relative(const Vec3& p) const
  {
    return { static_cast<float>(p.x() - Corner.x()), static_cast<float>(p.y() - Corner.y()),
      static_cast<float>(p.z() - Corner.z()) };
  }
  /// Absolute widening for a query at `p`: each stored coordinate is off by at most 2^-24 of
  /// its magnitude (the box's extent for entries, p's own offset for a query outside the
  /// box), and a difference of two by three such roundings; 2^-20 covers that sixteen times.
  float filterSlack(const Vec3& p) const
  {
    const double offset = (p - Corner).cwiseAbs().maxCoeff();
    return static_cast<float>(0x1p-20 * std::max(Extent, offset));
  }
  template <typename Scan>
  void scanDense(std::int64_t ix, std::int64_t iy, std::int64_t iz, const Scan& scan) const;
  template <typename Scan>
  void scanHashed(std::int64_t ix, std::int64_t iy, std::int64_t iz, const Scan& scan) const;
  /// hit(s) for every sorted entry s in [s, e) within reach of q and of another group than
  /// `group` (and, with CheckAfter, with item > after), four entries at a time.
  template <bool CheckAfter, typename Hit>
  void scanRange(std::uint32_t s, std::uint32_t e, const FloatPoint& q, float reach, float slack, std::int32_t group,
    std::int32_t after, const Hit& hit) const;
  /// visitEntry(s) for every sorted entry s with item > `after` within reach of p (and of
  /// another group than `group`).
  template <typename VisitEntry>
  void forEachEntryNear(const Vec3& p, double reach, std::int32_t group, std::int32_t after,
    const VisitEntry& visitEntry) const;

  double InverseCell = 1.0;
  bool Dense = false;
  std::int64_t Origin[3] = { 0, 0, 0 }; ///< dense: the box's first cell
  std::int64_t Cells[3] = { 0, 0, 0 };  ///< dense: cells per axis
  std::uint64_t Mask = 0;               ///< hashed: table size - 1
  Vec3 Corner = Vec3::Zero();           ///< the points' lowest corner: the filter's origin
  double Extent = 0.0;                  ///< the points' largest span along an axis
  std::vector<std::uint32_t> BucketStart; ///< prefix sums: bucket b holds [start[b], start[b+1])
  // The sorted entries (by bucket, stable: ascending items in each), as parallel arrays: the
  // filter streams x, y, z, reach and group; the rest is read only for the query entry or a hit.
  std::vector<float> X, Y, Z;
  std::vector<float> Reach;             ///< to the nearest float (kReachGrowth covers the rounding)
  std::vector<std::int32_t> Groups;     ///< without groups: the item itself (no two alike)
  std::vector<std::int32_t> Items;
  std::vector<Vec3> Positions;          ///< in double: a query entry's cell is computed as in the build
  std::vector<std::int64_t> ScratchCells;
  std::vector<std::uint32_t> ScratchBuckets;
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

/// Bit k set where lane k of a comparison's mask is (one instruction on x86-64).
inline unsigned laneBits(std::int32_t __attribute__((vector_size(16))) mask)
{
#if defined(__SSE2__)
  return static_cast<unsigned>(__builtin_ia32_movmskps(reinterpret_cast<float __attribute__((vector_size(16)))>(mask)));
#else
  return (mask[0] != 0 ? 1u : 0u) | (mask[1] != 0 ? 2u : 0u) | (mask[2] != 0 ? 4u : 0u) | (mask[3] != 0 ? 8u : 0u);
#endif
}

template <bool CheckAfter, typename Hit>
void UniformGrid::scanRange(std::uint32_t s, std::uint32_t e, const FloatPoint& q, float reach, float slack,
  std::int32_t group, std::int32_t after, const Hit& hit) const
{
  // Four entries at a time (GCC/Clang vector extensions: SSE on any x86-64); the arrays are
  // padded by kLanes - 1 entries, so a last partial group reads padding, masked by its index.
  using Floats = float __attribute__((vector_size(16)));
  using Ints = std::int32_t __attribute__((vector_size(16)));
  auto load = [](const auto* from, auto& into) { std::memcpy(&into, from, sizeof(into)); };
  const Floats qx = { q.x, q.x, q.x, q.x }, qy = { q.y, q.y, q.y, q.y }, qz = { q.z, q.z, q.z, q.z };
  const Floats lanesReach = { reach, reach, reach, reach }, lanesSlack = { slack, slack, slack, slack };
  const Ints lanesGroup = { group, group, group, group }, lanesAfter = { after, after, after, after };
  const Ints laneIndex = { 0, 1, 2, 3 };
  for (; s < e; s += kLanes)
  {
    Floats x, y, z, r;
    Ints g;
    load(&X[s], x);
    load(&Y[s], y);
    load(&Z[s], z);
    load(&Reach[s], r);
    load(&Groups[s], g);
    const Floats dx = x - qx, dy = y - qy, dz = z - qz;
    const Floats within = (lanesReach + r) * kReachGrowth + lanesSlack;
    const Ints left = { static_cast<std::int32_t>(e - s), static_cast<std::int32_t>(e - s),
      static_cast<std::int32_t>(e - s), static_cast<std::int32_t>(e - s) };
    Ints near = (dx * dx + dy * dy + dz * dz <= within * within) & (g != lanesGroup) & (laneIndex < left);
    if constexpr (CheckAfter)
    {
      Ints item;
      load(&Items[s], item);
      near = near & (item > lanesAfter);
    }
    // Most groups of four hold no hit: one test for all four, then the hits' lanes in order.
    for (unsigned lanes = laneBits(near); lanes != 0; lanes &= lanes - 1)
    {
      hit(s + static_cast<std::uint32_t>(std::countr_zero(lanes)));
    }
  }
}

template <typename VisitEntry>
void UniformGrid::forEachEntryNear(const Vec3& p, double reach, std::int32_t group, std::int32_t after,
  const VisitEntry& visitEntry) const
{
  if (Positions.empty())
  {
    return;
  }
  const FloatPoint q = relative(p);
  const float slack = filterSlack(p);
  // Rounded to nearest: kReachGrowth covers that rounding too.
  const auto reachFloat = static_cast<float>(reach);
  auto scan = [&](std::uint32_t s, std::uint32_t e) { scanRange<true>(s, e, q, reachFloat, slack, group, after, visitEntry); };
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
  // A query point is of no group: every group is another one.
  forEachEntryNear(p, reach, kNoGroup, after, [&](std::uint32_t s) { visit(Items[s]); });
}

template <typename VisitPair>
void UniformGrid::forEachPairFrom(std::size_t entry, const VisitPair& visitPair) const
{
  const Vec3& position = Positions[entry];
  const std::int32_t item = Items[entry];
  const std::int32_t group = Groups[entry];
  if (!Dense)
  {
    forEachEntryNear(position, static_cast<double>(Reach[entry]), group, item,
      [&](std::uint32_t s) { visitPair(item, Items[s]); });
    return;
  }
  const FloatPoint q{ X[entry], Y[entry], Z[entry] };
  const float slack = filterSlack(position);
  const float reach = Reach[entry];
  auto scan = [&](std::uint32_t s, std::uint32_t e) {
    scanRange<false>(s, e, q, reach, slack, group, 0, [&](std::uint32_t other) {
      visitPair(std::min(item, Items[other]), std::max(item, Items[other]));
    });
  };
  // The same cell the build computed (same position, same scale), in box coordinates.
  const std::int64_t x = cellOf(position.x()) - Origin[0];
  const std::int64_t y = cellOf(position.y()) - Origin[1];
  const std::int64_t z = cellOf(position.z()) - Origin[2];
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
