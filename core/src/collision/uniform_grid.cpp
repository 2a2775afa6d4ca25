#include "softbody/collision/uniform_grid.h"

#include "softbody/common/parallel.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

namespace softbody
{

namespace
{

/// The smallest float >= value: a reach stored in single precision never shrinks.
float roundedUp(double value)
{
  auto f = static_cast<float>(value);
  if (static_cast<double>(f) < value)
  {
    f = std::nextafter(f, std::numeric_limits<float>::infinity());
  }
  return f;
}

} // namespace

void UniformGrid::build(const std::vector<Vec3>& positions, const std::vector<double>& reaches, double cellSize,
  const std::vector<std::int32_t>& groups)
{
  const std::size_t n = positions.size();
  InverseCell = cellSize > 0.0 ? 1.0 / cellSize : 1.0;
  // Scratch kept between builds: freeing and re-mapping these megabytes each detection would
  // cost page faults.
  std::vector<std::int64_t>& cells = ScratchCells;
  cells.resize(3 * n);
  parallelFor(n, 4096, [&](std::size_t i) {
    for (int a = 0; a < 3; ++a)
    {
      cells[3 * i + a] = cellOf(positions[i][a]);
    }
  });
  // The cell box, and whether a dense index over it is small enough.
  std::int64_t lo[3], hi[3];
  for (int a = 0; a < 3; ++a)
  {
    lo[a] = std::numeric_limits<std::int64_t>::max();
    hi[a] = std::numeric_limits<std::int64_t>::min();
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    for (int a = 0; a < 3; ++a)
    {
      lo[a] = std::min(lo[a], cells[3 * i + a]);
      hi[a] = std::max(hi[a], cells[3 * i + a]);
    }
  }
  const std::uint64_t denseLimit = kDenseCellsPerPoint * std::max<std::uint64_t>(n, 64);
  double denseCells = 1.0; // in double: the spans of far-apart points overflow integers
  for (int a = 0; a < 3 && n > 0; ++a)
  {
    denseCells *= static_cast<double>(hi[a]) - static_cast<double>(lo[a]) + 1.0;
  }
  Dense = n > 0 && denseCells <= static_cast<double>(denseLimit);
  std::uint64_t size = 0;
  if (Dense)
  {
    for (int a = 0; a < 3; ++a)
    {
      Origin[a] = lo[a];
      Cells[a] = hi[a] - lo[a] + 1;
    }
    size = static_cast<std::uint64_t>(Cells[0] * Cells[1] * Cells[2]);
  }
  else
  {
    // About two buckets per point: few shared buckets, the table small next to the entries.
    size = std::bit_ceil(std::max<std::uint64_t>(2 * n, 64));
    Mask = size - 1;
  }

  std::vector<std::uint32_t>& bucket = ScratchBuckets;
  bucket.resize(n);
  parallelFor(n, 4096, [&](std::size_t i) {
    const std::int64_t* c = &cells[3 * i];
    bucket[i] = static_cast<std::uint32_t>(Dense
        ? static_cast<std::uint64_t>(((c[2] - Origin[2]) * Cells[1] + (c[1] - Origin[1])) * Cells[0] + (c[0] - Origin[0]))
        : hashedBucket(c[0], c[1], c[2]));
  });
  // Counting sort: histogram, exclusive prefix sums, stable scatter. Sequential: a parallel
  // histogram without atomics needs one table per chunk.
  BucketStart.assign(size + 1, 0);
  for (std::uint32_t b : bucket)
  {
    ++BucketStart[b + 1];
  }
  for (std::uint64_t b = 0; b < size; ++b)
  {
    BucketStart[b + 1] += BucketStart[b];
  }
  std::vector<std::int32_t>& items = ScratchItems;
  items.resize(n);
  {
    std::vector<std::uint32_t>& next = ScratchNext;
    next.assign(BucketStart.begin(), BucketStart.end() - 1);
    for (std::size_t i = 0; i < n; ++i)
    {
      items[next[bucket[i]]++] = static_cast<std::int32_t>(i);
    }
  }
  Entries.resize(n);
  EntryGroups.resize(groups.empty() ? 0 : n);
  parallelFor(n, 4096, [&](std::size_t s) {
    Entries[s].position = positions[items[s]];
    Entries[s].reach = roundedUp(reaches[items[s]]);
    Entries[s].item = items[s];
    if (!groups.empty())
    {
      EntryGroups[s] = groups[static_cast<std::size_t>(items[s])];
    }
  });
}

} // namespace softbody
