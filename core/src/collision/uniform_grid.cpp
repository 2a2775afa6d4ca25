#include "softbody/collision/uniform_grid.h"

#include "softbody/common/parallel.h"

#include <algorithm>
#include <bit>
#include <limits>
#include <stdexcept>
#include <string>

namespace softbody
{

namespace
{

/// The points' cell box and coordinate box.
struct Bounds
{
  std::int64_t lo[3] = { std::numeric_limits<std::int64_t>::max(), std::numeric_limits<std::int64_t>::max(),
    std::numeric_limits<std::int64_t>::max() };
  std::int64_t hi[3] = { std::numeric_limits<std::int64_t>::min(), std::numeric_limits<std::int64_t>::min(),
    std::numeric_limits<std::int64_t>::min() };
  Vec3 lowest = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 highest = Vec3::Constant(-std::numeric_limits<double>::infinity());

  Bounds& include(const Bounds& other)
  {
    for (int a = 0; a < 3; ++a)
    {
      lo[a] = std::min(lo[a], other.lo[a]);
      hi[a] = std::max(hi[a], other.hi[a]);
    }
    lowest = lowest.cwiseMin(other.lowest);
    highest = highest.cwiseMax(other.highest);
    return *this;
  }
};

} // namespace

void UniformGrid::build(const std::vector<Vec3>& positions, const std::vector<double>& reaches, double cellSize,
  const std::vector<std::int32_t>& groups)
{
  const std::size_t n = positions.size();
  if (!groups.empty() && (groups.size() != n || std::find(groups.begin(), groups.end(), kNoGroup) != groups.end()))
  {
    throw std::invalid_argument("UniformGrid: " + std::to_string(groups.size()) + " groups for " + std::to_string(n) +
      " points, or a group of " + std::to_string(kNoGroup) + " (reserved for query points)");
  }
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
  // The cell box, and whether a dense index over it is small enough; the points' box, the
  // single-precision filter's origin. (Minima and maxima: exact in any order.)
  const Bounds bounds = parallelReduce(n, 4096, Bounds{},
    [&](std::size_t i) {
      Bounds one;
      for (int a = 0; a < 3; ++a)
      {
        one.lo[a] = one.hi[a] = cells[3 * i + a];
      }
      one.lowest = one.highest = positions[i];
      return one;
    },
    [](Bounds x, const Bounds& y) { return x.include(y); });
  const std::int64_t* lo = bounds.lo;
  const std::int64_t* hi = bounds.hi;
  Corner = n > 0 ? bounds.lowest : Vec3::Zero();
  Extent = n > 0 ? (bounds.highest - bounds.lowest).maxCoeff() : 0.0;
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
  Items.resize(n);
  {
    std::vector<std::uint32_t>& next = ScratchNext;
    next.assign(BucketStart.begin(), BucketStart.end() - 1);
    for (std::size_t i = 0; i < n; ++i)
    {
      Items[next[bucket[i]]++] = static_cast<std::int32_t>(i);
    }
  }
  // Padded for the filter's last group of kLanes (masked out; zeros, so no NaN is computed).
  for (auto* lanes : { &X, &Y, &Z, &Reach })
  {
    lanes->resize(n + kLanes - 1);
    std::fill(lanes->begin() + static_cast<std::ptrdiff_t>(n), lanes->end(), 0.0f);
  }
  for (auto* lanes : { &Groups, &Items })
  {
    lanes->resize(n + kLanes - 1);
    std::fill(lanes->begin() + static_cast<std::ptrdiff_t>(n), lanes->end(), 0);
  }
  Positions.resize(n);
  parallelFor(n, 4096, [&](std::size_t s) {
    const auto item = static_cast<std::size_t>(Items[s]);
    const Vec3& p = positions[item];
    const FloatPoint q = relative(p);
    X[s] = q.x;
    Y[s] = q.y;
    Z[s] = q.z;
    Reach[s] = static_cast<float>(reaches[item]); // rounded to nearest: kReachGrowth covers it
    Groups[s] = groups.empty() ? Items[s] : groups[item];
    Positions[s] = p;
  });
}

} // namespace softbody
