// The only parallel patterns core uses, in one place:
//   parallelFor(count, grain, body)      body(i) for every i; each i is written by one task
//   parallelForContiguous(count, grain, body)   the same, one contiguous part per thread
//   parallelReduce(count, grain, init, map, combine)   an order-independent reduction
//   parallelSum(count, term)             a floating-point sum with a fixed summation order
// Kernels stay plain loops over indices and never see the threading library.
//
// The normal backend is TBB. ThreadSanitizer cannot see the synchronization inside Debian's
// uninstrumented libtbb (every hand-off between TBB threads looks like a race), so a
// ThreadSanitizer build (SOFTBODY_PARALLEL_STD_THREADS) runs the same loops on std::thread,
// which TSan does understand: the kernels are still checked under real concurrency.
#pragma once

#include <tbb/global_control.h>

#include <algorithm>
#include <cstddef>
#include <vector>

#ifdef SOFTBODY_PARALLEL_STD_THREADS
#include <algorithm>
#include <thread>
#include <vector>
#else
#include <tbb/blocked_range.h>
#include <tbb/partitioner.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#endif

namespace softbody
{

#ifdef SOFTBODY_PARALLEL_STD_THREADS

namespace detail
{
/// One chunk per allowed thread (TBB's global_control limit applies here too, so thread-count
/// tests mean the same thing).
inline std::size_t chunkCount(std::size_t count)
{
  return std::max<std::size_t>(1,
    std::min(count, tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)));
}

/// Runs chunkBody(chunk, begin, end) over contiguous chunks of [0, count), one thread each.
template <typename ChunkBody>
void runChunks(std::size_t count, const ChunkBody& chunkBody)
{
  const std::size_t threads = chunkCount(count);
  std::vector<std::thread> workers;
  for (std::size_t t = 1; t < threads; ++t)
  {
    workers.emplace_back([&, t] { chunkBody(t, count * t / threads, count * (t + 1) / threads); });
  }
  chunkBody(0, 0, count / threads);
  for (std::thread& worker : workers)
  {
    worker.join();
  }
}
} // namespace detail

template <typename Function>
void parallelFor(std::size_t count, std::size_t /*grain*/, const Function& body)
{
  detail::runChunks(count, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      body(i);
    }
  });
}

template <typename Function>
void parallelForContiguous(std::size_t count, std::size_t grain, const Function& body)
{
  parallelFor(count, grain, body); // already one contiguous chunk per thread
}

template <typename T, typename Map, typename Combine>
T parallelReduce(std::size_t count, std::size_t /*grain*/, T identity, const Map& map, const Combine& combine)
{
  // One whole object per chunk: a plain std::vector<bool> would pack the chunks' results into
  // one word and make their writes race.
  struct Slot
  {
    T value;
  };
  std::vector<Slot> partial(detail::chunkCount(count), Slot{ identity });
  detail::runChunks(count, [&](std::size_t chunk, std::size_t begin, std::size_t end) {
    T value = identity;
    for (std::size_t i = begin; i < end; ++i)
    {
      value = combine(value, map(i));
    }
    partial[chunk].value = value;
  });
  T result = identity;
  for (const Slot& slot : partial)
  {
    result = combine(result, slot.value);
  }
  return result;
}

#else

template <typename Function>
void parallelFor(std::size_t count, std::size_t grain, const Function& body)
{
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, grain),
    [&](const tbb::blocked_range<std::size_t>& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i)
      {
        body(i);
      }
    });
}

/// body(i) for every i, split evenly into one contiguous part per thread without load
/// balancing (TBB's static partitioner, which also gives each part to the same thread from call
/// to call). For loop after loop over data laid out in the same order, such as the colors of a
/// constraint graph sorted by vertex: each core keeps touching the same part of the vertices,
/// so they stay in its cache instead of moving between the cores every color, and two threads
/// never interleave writes to neighbouring vertices. Ranges below 2 grains run on the caller.
template <typename Function>
void parallelForContiguous(std::size_t count, std::size_t grain, const Function& body)
{
  if (count < 2 * grain)
  {
    for (std::size_t i = 0; i < count; ++i)
    {
      body(i);
    }
    return;
  }
  tbb::parallel_for(
    tbb::blocked_range<std::size_t>(0, count, grain),
    [&](const tbb::blocked_range<std::size_t>& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i)
      {
        body(i);
      }
    },
    tbb::static_partitioner());
}

/// `combine` must be associative and commutative up to the exactness the caller needs (max,
/// integer sums): TBB may split and join in any order.
template <typename T, typename Map, typename Combine>
T parallelReduce(std::size_t count, std::size_t grain, T identity, const Map& map, const Combine& combine)
{
  return tbb::parallel_reduce(
    tbb::blocked_range<std::size_t>(0, count, grain), identity,
    [&](const tbb::blocked_range<std::size_t>& range, T value) {
      for (std::size_t i = range.begin(); i != range.end(); ++i)
      {
        value = combine(value, map(i));
      }
      return value;
    },
    combine);
}

#endif

/// Sum of term(i) over [0, count) that is bitwise the same for any thread count: the terms are
/// summed in fixed blocks of kSumBlock (in parallel), then the block sums in order. A plain
/// parallelReduce would add in whatever order the scheduler splits the range.
template <typename Term>
double parallelSum(std::size_t count, const Term& term)
{
  constexpr std::size_t kSumBlock = 2048;
  const std::size_t blocks = (count + kSumBlock - 1) / kSumBlock;
  std::vector<double> partial(blocks, 0.0);
  parallelFor(blocks, 1, [&](std::size_t b) {
    double sum = 0.0;
    const std::size_t end = std::min(count, (b + 1) * kSumBlock);
    for (std::size_t i = b * kSumBlock; i < end; ++i)
    {
      sum += term(i);
    }
    partial[b] = sum;
  });
  double total = 0.0;
  for (double value : partial)
  {
    total += value;
  }
  return total;
}

} // namespace softbody
