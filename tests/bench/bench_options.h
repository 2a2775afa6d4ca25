// What every benchmark program shares: its command line and a hash of a final state (equal
// hashes at every thread count show the runs computed the same thing).
#pragma once

#include "softbody/common/geometry.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

namespace softbody::bench
{

struct Options
{
  bool smoke = false;                  ///< --smoke: a few seconds, for CTest
  std::string dataDir = "../shared/data"; ///< --data: the public meshes, when present
  std::string csv;                     ///< --csv: output file (or prefix)
  /// --mesh: only this mesh (bench_meshes.h meshFromSpec: "ellipsoid180k", a benchmark mesh's
  /// name, or a .node/.ele, .msh or .obj file)
  std::string mesh;
  int repeat = 1; ///< --repeat: timed runs per case; the minimum and the median are printed
};

/// The Markdown table's path beside a CSV: name.csv -> name.md (the docs pages' tables,
/// scripts/update_docs_tables.py).
inline std::string tableBeside(const std::string& csv)
{
  const bool isCsv = csv.size() > 4 && csv.compare(csv.size() - 4, 4, ".csv") == 0;
  return (isCsv ? csv.substr(0, csv.size() - 4) : csv) + ".md";
}

/// Parses --smoke, --data DIR, --csv PATH, --mesh SPEC, --repeat N; prints the usage and exits on anything else.
inline Options parseOptions(int argc, char** argv, const std::string& program, const std::string& defaultCsv)
{
  Options options;
  options.csv = defaultCsv;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "--smoke")
    {
      options.smoke = true;
    }
    else if (arg == "--data" && i + 1 < argc)
    {
      options.dataDir = argv[++i];
    }
    else if (arg == "--csv" && i + 1 < argc)
    {
      options.csv = argv[++i];
    }
    else if (arg == "--mesh" && i + 1 < argc)
    {
      options.mesh = argv[++i];
    }
    else if (arg == "--repeat" && i + 1 < argc && std::atoi(argv[i + 1]) >= 1)
    {
      options.repeat = std::atoi(argv[++i]);
    }
    else
    {
      std::cerr << "usage: " << program
                << " [--smoke] [--data DIR] [--csv PATH] [--mesh NAME|FILE] [--repeat N]\n";
      std::exit(2);
    }
  }
  return options;
}

/// FNV-1a over the bytes of the positions.
inline std::uint64_t hashPositions(const std::vector<Vec3>& x)
{
  std::uint64_t hash = 1469598103934665603ull;
  const auto* bytes = reinterpret_cast<const unsigned char*>(x.data());
  for (std::size_t i = 0; i < x.size() * sizeof(Vec3); ++i)
  {
    hash = (hash ^ bytes[i]) * 1099511628211ull;
  }
  return hash;
}

} // namespace softbody::bench

namespace softbody::bench
{
/// CPU time of the calling thread [s]. On a shared machine a single-threaded run's CPU time
/// leaves out the time other processes held the core (its wall time does not), so 1-thread rows
/// also print it; with several threads the work runs on TBB's workers too, and only wall time
/// means anything.
inline double threadCpuSeconds()
{
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

/// The minimum and the median of some timings.
struct MinMedian
{
  double min = 0.0;
  double median = 0.0;
};
/// Least seconds per call of `work` over `repeat` groups of `calls` calls: the calling thread's
/// CPU time (`cpu`: leaves out other processes' turns on the core) or wall time.
template <class Work>
double leastSecondsPerCall(int repeat, int calls, bool cpu, const Work& work)
{
  double least = 1e300;
  for (int r = 0; r < repeat; ++r)
  {
    const auto wall0 = std::chrono::steady_clock::now();
    const double cpu0 = threadCpuSeconds();
    for (int i = 0; i < calls; ++i)
    {
      work();
    }
    const double seconds =
      cpu ? threadCpuSeconds() - cpu0 : std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    least = std::min(least, seconds / calls);
  }
  return least;
}

inline MinMedian minMedian(std::vector<double> values)
{
  std::sort(values.begin(), values.end());
  if (values.empty())
  {
    return {};
  }
  const std::size_t n = values.size();
  return { values.front(), n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]) };
}
} // namespace softbody::bench
