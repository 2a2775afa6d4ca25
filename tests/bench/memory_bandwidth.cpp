#include "memory_bandwidth.h"

// Through core's parallelFor (a TBB blocked_range underneath), not TBB directly: a
// ThreadSanitizer build runs it on std::thread, whose hand-offs TSan sees. Called straight on
// TBB, TSan reports 36 races inside TBB's own task objects (partitioner,
// blocked_range) in bench.mass_spring_smoke: Debian's libtbb is not instrumented.
#include "softbody/common/parallel.h"

#include <algorithm>
#include <chrono>
#include <vector>

namespace softbody::bench
{

double measureTriadBandwidth(std::size_t elements, int repetitions)
{
  std::vector<double> a(elements), b(elements, 1.0), c(elements, 2.0);
  double best = 1e30;
  for (int r = 0; r < repetitions; ++r)
  {
    const auto start = std::chrono::steady_clock::now();
    softbody::parallelFor(elements, std::size_t(1) << 16, [&](std::size_t i) { a[i] = b[i] + 3.0 * c[i]; });
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  volatile double sink = a[elements / 2]; // keep the stores observable
  (void)sink;
  return 3.0 * sizeof(double) * double(elements) / best;
}

namespace
{
/// A dependent chain of multiply-adds per index: compute-bound, in registers.
double chain(std::size_t seed)
{
  double x = 1.0 + 1e-9 * double(seed);
  for (int k = 0; k < 20000; ++k)
  {
    x = x * 0.999999 + 1e-7;
  }
  return x;
}

double bestSeconds(std::size_t tasks, int repetitions, bool parallel)
{
  std::vector<double> out(tasks);
  double best = 1e30;
  for (int r = 0; r < repetitions; ++r)
  {
    const auto start = std::chrono::steady_clock::now();
    if (parallel)
    {
      softbody::parallelFor(tasks, 1, [&](std::size_t i) { out[i] = chain(i); });
    }
    else
    {
      for (std::size_t i = 0; i < tasks; ++i)
      {
        out[i] = chain(i);
      }
    }
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  volatile double sink = out[tasks / 2];
  (void)sink;
  return best;
}
} // namespace

double measureComputeParallelism(int repetitions)
{
  const std::size_t tasks = 256;
  return bestSeconds(tasks, repetitions, false) / bestSeconds(tasks, repetitions, true);
}

} // namespace softbody::bench
