#include "memory_bandwidth.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

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
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, elements, 1 << 16),
      [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i)
        {
          a[i] = b[i] + 3.0 * c[i];
        }
      });
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  volatile double sink = a[elements / 2]; // keep the stores observable
  (void)sink;
  return 3.0 * sizeof(double) * double(elements) / best;
}

} // namespace softbody::bench
