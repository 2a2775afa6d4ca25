#include "softbody/collision/uniform_grid.h"

#include "softbody/common/parallel.h"

#include <bit>

namespace softbody
{

void UniformGrid::build(const std::vector<Vec3>& positions, const std::vector<double>& reaches, double cellSize)
{
  const std::size_t n = positions.size();
  InverseCell = cellSize > 0.0 ? 1.0 / cellSize : 1.0;
  // About two buckets per point: few shared buckets, and the table stays small next to the
  // points' own data.
  const std::uint64_t size = std::bit_ceil(std::max<std::uint64_t>(2 * n, 64));
  Mask = size - 1;

  std::vector<std::uint32_t> bucket(n);
  parallelFor(n, 4096, [&](std::size_t i) {
    bucket[i] = static_cast<std::uint32_t>(bucketOf(cellOf(positions[i].x()), cellOf(positions[i].y()), cellOf(positions[i].z())));
  });
  // Counting sort: histogram, exclusive prefix sums, stable scatter. Sequential: one pass of
  // increments over n items and the table (about a tenth of the queries' time, measured in
  // bench_collision); a parallel histogram needs one table per chunk.
  BucketStart.assign(size + 1, 0);
  for (std::uint32_t b : bucket)
  {
    ++BucketStart[b + 1];
  }
  for (std::uint64_t b = 0; b < size; ++b)
  {
    BucketStart[b + 1] += BucketStart[b];
  }
  Items.resize(n);
  {
    std::vector<std::uint32_t> next(BucketStart.begin(), BucketStart.end() - 1);
    for (std::size_t i = 0; i < n; ++i)
    {
      Items[next[bucket[i]]++] = static_cast<std::int32_t>(i);
    }
  }
  SortedPositions.resize(n);
  SortedReaches.resize(n);
  parallelFor(n, 4096, [&](std::size_t s) {
    SortedPositions[s] = positions[Items[s]];
    SortedReaches[s] = reaches[Items[s]];
  });
}

} // namespace softbody
