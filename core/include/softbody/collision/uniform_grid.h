// The uniform-grid broad phase for points: a counting-sort hash grid (Teschner et al. 2003,
// "Optimized Spatial Hashing for Collision Detection of Deformable Objects"; Green 2008,
// "Particle Simulation using CUDA"). Each point's cell is hashed to a bucket, the points are
// counting-sorted by bucket (histogram, prefix sums, scatter), and their positions and reaches
// are copied into that order so a query reads contiguous memory.
//
// The hash keeps consecutive x cells in consecutive buckets, bucket = (ix + H(iy, iz)) mod size,
// so a query reads the 3 x 3 x 3 neighbourhood as 9 runs of 3 buckets: 9 ranges of the sorted
// arrays rather than 27 lookups. Different cells sharing a bucket only add candidates that the
// distance test rejects; runs that overlap are merged so no point is visited twice.
#pragma once

#include "softbody/common/geometry.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace softbody
{

class UniformGrid
{
public:
  /// Sorts items 0..n-1 (positions, reaches) into cells of `cellSize`, which must be at least
  /// twice the largest reach so that every pair within reach_i + reach_j is in neighbouring
  /// cells. Deterministic: the sort is stable, items of one bucket stay in index order.
  void build(const std::vector<Vec3>& positions, const std::vector<double>& reaches, double cellSize);

  /// visit(item) for every item j with |p - x_j| <= reach + reach_j (each once; items sharing
  /// a bucket with the neighbourhood may be visited too: the caller's exact test decides).
  template <typename Visit>
  void forEachNear(const Vec3& p, double reach, const Visit& visit) const;

  std::size_t bucketCount() const { return BucketStart.empty() ? 0 : BucketStart.size() - 1; }

private:
  std::int64_t cellOf(double coordinate) const
  {
    return static_cast<std::int64_t>(std::floor(coordinate * InverseCell));
  }
  std::uint64_t rowHash(std::int64_t iy, std::int64_t iz) const
  {
    return static_cast<std::uint64_t>(iy) * 73856093ull ^ static_cast<std::uint64_t>(iz) * 19349663ull;
  }
  std::uint64_t bucketOf(std::int64_t ix, std::int64_t iy, std::int64_t iz) const
  {
    return (static_cast<std::uint64_t>(ix) + rowHash(iy, iz)) & Mask;
  }

  double InverseCell = 1.0;
  std::uint64_t Mask = 0;
  std::vector<std::uint32_t> BucketStart; ///< prefix sums: bucket b holds [start[b], start[b+1])
  std::vector<std::int32_t> Items;        ///< items sorted by bucket
  std::vector<Vec3> SortedPositions;
  std::vector<double> SortedReaches;
};

template <typename Visit>
void UniformGrid::forEachNear(const Vec3& p, double reach, const Visit& visit) const
{
  if (Items.empty())
  {
    return;
  }
  const std::int64_t ix = cellOf(p.x()), iy = cellOf(p.y()), iz = cellOf(p.z());
  // The 9 runs [b, b + 3) of buckets, split where they wrap around the table.
  std::array<std::uint64_t, 18> begin{}, end{};
  int runs = 0;
  const std::uint64_t size = Mask + 1;
  for (std::int64_t dz = -1; dz <= 1; ++dz)
  {
    for (std::int64_t dy = -1; dy <= 1; ++dy)
    {
      const std::uint64_t first = bucketOf(ix - 1, iy + dy, iz + dz);
      if (first + 3 <= size)
      {
        begin[runs] = first, end[runs] = first + 3, ++runs;
      }
      else
      {
        begin[runs] = first, end[runs] = size, ++runs;
        begin[runs] = 0, end[runs] = first + 3 - size, ++runs;
      }
    }
  }
  // Insertion sort of the runs by start, then merged: each bucket read once.
  for (int i = 1; i < runs; ++i)
  {
    for (int j = i; j > 0 && begin[j] < begin[j - 1]; --j)
    {
      std::swap(begin[j], begin[j - 1]);
      std::swap(end[j], end[j - 1]);
    }
  }
  std::uint64_t from = begin[0], to = end[0];
  auto scan = [&](std::uint64_t b0, std::uint64_t b1) {
    for (std::uint32_t s = BucketStart[b0], e = BucketStart[b1]; s < e; ++s)
    {
      const double within = reach + SortedReaches[s];
      if ((SortedPositions[s] - p).squaredNorm() <= within * within)
      {
        visit(Items[s]);
      }
    }
  };
  for (int i = 1; i < runs; ++i)
  {
    if (begin[i] <= to)
    {
      to = std::max(to, end[i]);
    }
    else
    {
      scan(from, to);
      from = begin[i], to = end[i];
    }
  }
  scan(from, to);
}

} // namespace softbody
