// Collision detection (broad + narrow phase, one CollisionDetector::detect call), after the
// PBD thesis's figures:
//
// 1. Figure 5.1: time per detection of each broad phase (brute force, uniform grid, octree) at
//    8,000 particles settled in a box (a packed lattice) and in a pile (a cone), at 1 and all
//    threads, with the ratio grid vs brute force measured in the same run.
// 2. Figure 5.2: the uniform grid at 1 thread against all threads from 500 to 20,000
//    particles, extended to 100,000 and 1,000,000, with the speed-up.
// 3. The crossover that sets BroadPhase::Automatic: brute force against the grid on small
//    scenes, as pair tests per detection.
//
// The particles are voxel-like spheres of radius r on a lattice of spacing 2 r (touching), a
// little jittered, grouped into bodies of 5 x 5 x 5 that collide with each other
// (ObstaclesAndBodies) and with the floor; each point moved by one substep of free fall from
// start to predicted. Every time is the minimum over --repeat runs (other processes share the
// machine), the median beside it; figure 5.2 also prints the least CPU time at one thread,
// which other processes' turns on the cores do not inflate.
//
// Figure 5.2 also prints each detection's bound in the same run: the bytes any detection must
// move (each point's start and predicted position, radius and body read once; each contact
// written once) at the triad bandwidth measured at the start, so "x bound" says how far the
// detection is from streaming its inputs and outputs.
//
// Besides the CSV, figures 5.1 and 5.2 as Markdown tables in a file beside it (name.csv ->
// name.md), which scripts/bench.sh writes into docs/performance.md.
//
// Usage: bench_collision [--smoke] [--csv PATH] [--repeat N]
#include "bench_options.h"
#include "memory_bandwidth.h"

#include "softbody/collision/collision_detector.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <random>
#include <string>
#include <ctime>

using namespace softbody;

namespace
{

constexpr double kRadius = 0.005; // [m]
constexpr double kStep = 0.005;   // substep [s]

struct ParticleScene
{
  CollisionGeometry geometry;
  std::vector<Vec3> start, predicted;
};

/// About `count` particles: a cube lattice ("box") or the lattice points under a cone
/// ("pile"), jittered by 5 % of the spacing; bodies of 5 x 5 x 5 lattice cells.
ParticleScene particleScene(std::size_t count, bool pile)
{
  ParticleScene scene;
  const double spacing = 2.0 * kRadius;
  // A cone of height H over radius H holds pi/3 H^3 cells per spacing^3: size the lattice so
  // the kept points number about `count`.
  const double cells = pile ? std::cbrt(static_cast<double>(count) * 3.0 / (3.14159265358979 / 3.0) / 4.0)
                            : std::cbrt(static_cast<double>(count));
  const int n = std::max(1, static_cast<int>(std::ceil(pile ? 2.0 * cells : cells)));
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> jitter(-0.05 * spacing, 0.05 * spacing);
  for (int k = 0; k < n && scene.geometry.rest.size() < count; ++k)
  {
    for (int j = 0; j < n && scene.geometry.rest.size() < count; ++j)
    {
      for (int i = 0; i < n && scene.geometry.rest.size() < count; ++i)
      {
        if (pile)
        {
          const double dx = i - 0.5 * n, dy = j - 0.5 * n;
          if (std::sqrt(dx * dx + dy * dy) > 0.5 * n - k)
          {
            continue;
          }
        }
        const Vec3 p = Vec3(i, j, k) * spacing + Vec3(0, 0, kRadius) + Vec3(jitter(rng), jitter(rng), jitter(rng));
        scene.geometry.collidingPoints.push_back(static_cast<std::int32_t>(scene.geometry.rest.size()));
        scene.geometry.rest.push_back(p);
        scene.geometry.bodyOf.push_back((i / 5) + 1000 * ((j / 5) + 1000 * (k / 5)));
        scene.geometry.radius.push_back(kRadius);
      }
    }
  }
  scene.start = scene.geometry.rest;
  scene.predicted = scene.start;
  for (Vec3& p : scene.predicted)
  {
    p.z() -= 9.81 * kStep * kStep;
  }
  return scene;
}

struct Timing
{
  double minMs = 0.0;
  double medianMs = 0.0;
  double maxMs = 0.0; ///< the slowest run: "in every run" is a bound on this one
  double cpuMs = 0.0; ///< least process CPU time of one detection (all threads summed)
  std::size_t contacts = 0;
  std::size_t pairs = 0;
};

/// CPU time of this process [ms]: at one thread, the detection's own work even while other
/// processes take turns on the cores (wall time then includes their turns).
double processCpuMs()
{
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return 1e3 * static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_nsec);
}

Timing timeDetection(const ParticleScene& scene, BroadPhase kind, std::size_t threads, int repeat)
{
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  CollisionSettings settings;
  settings.mode = CollisionMode::ObstaclesAndBodies;
  settings.broadPhase = kind;
  CollisionDetector detector(scene.geometry, settings, true, FloorPlane{});
  ContactSet contacts;
  detector.detect(scene.start, scene.predicted, 0.0, kStep, contacts); // warm: first-use allocations
  std::vector<double> ms;
  double cpuMs = 1e300;
  for (int r = 0; r < repeat; ++r)
  {
    const double cpuBegin = processCpuMs();
    const auto begin = std::chrono::steady_clock::now();
    detector.detect(scene.start, scene.predicted, 0.0, kStep, contacts);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin).count());
    cpuMs = std::min(cpuMs, processCpuMs() - cpuBegin);
  }
  std::sort(ms.begin(), ms.end());
  return { ms.front(), ms[ms.size() / 2], ms.back(), cpuMs, contacts.size(), detector.stats().candidatePairs };
}

const char* kindName(BroadPhase kind)
{
  switch (kind)
  {
    case BroadPhase::BruteForce: return "brute force";
    case BroadPhase::UniformGrid: return "uniform grid";
    case BroadPhase::Octree: return "octree";
    default: return "automatic";
  }
}

} // namespace

int main(int argc, char** argv)
{
  const bench::Options options = bench::parseOptions(argc, argv, "bench_collision", "bench_collision.csv");
  const int repeat = options.smoke ? 1 : std::max(options.repeat, 5);
  const auto maxThreads = static_cast<std::size_t>(tbb::info::default_concurrency());
  std::ofstream csv(options.csv);
  csv << "figure,scene,particles,broad_phase,threads,ms_min,ms_median,cpu_ms_min,contacts,candidate_pairs\n";
  auto record = [&](const char* figure, const char* layout, std::size_t n, BroadPhase kind, std::size_t threads, const Timing& t) {
    csv << figure << ',' << layout << ',' << n << ',' << kindName(kind) << ',' << threads << ',' << t.minMs << ','
        << t.medianMs << ',' << t.cpuMs << ',' << t.contacts << ',' << t.pairs << '\n';
  };
  // The figures as tables for docs/performance.md (scripts/update_docs_tables.py).
  std::ofstream table(bench::tableBeside(options.csv));
  char cell[256];
  std::printf("Collision detection (broad + narrow phase), particles of radius %g m touching, %zu threads max,"
              " min (median) of %d runs\n", kRadius, maxThreads, repeat);

  // 1. Figure 5.1.
  const std::size_t fig1 = options.smoke ? 1000 : 8000;
  std::printf("\nFigure 5.1: %zu particles, ms per detection\n", fig1);
  std::printf("%-6s %-14s %8s %20s %20s %10s %10s\n", "scene", "broad phase", "contacts", "1 thread", "all threads", "2thr/1thr", "vs brute");
  table << "## Figure 5.1\n\n" << fig1 << " particles asked for (the pile keeps fewer), minimum (median) of " << repeat
        << " runs, ms per detection\n\n"
        << "| scene | particles | broad phase | contacts | 1 thread | " << maxThreads << " threads | speed-up | brute force / this |\n"
        << "|---|---:|---|---:|---:|---:|---:|---:|\n";
  for (bool pile : { false, true })
  {
    const ParticleScene scene = particleScene(fig1, pile);
    const char* layout = pile ? "pile" : "box";
    double bruteMs = 0.0;
    for (BroadPhase kind : { BroadPhase::BruteForce, BroadPhase::UniformGrid, BroadPhase::Octree })
    {
      const Timing one = timeDetection(scene, kind, 1, kind == BroadPhase::BruteForce ? std::min(repeat, 2) : repeat);
      const Timing all = timeDetection(scene, kind, maxThreads, kind == BroadPhase::BruteForce ? std::min(repeat, 2) : repeat);
      if (kind == BroadPhase::BruteForce)
      {
        bruteMs = all.minMs;
      }
      else if (one.contacts != timeDetection(scene, BroadPhase::BruteForce, maxThreads, 1).contacts)
      {
        std::printf("ERROR: %s found another number of contacts than brute force\n", kindName(kind));
        return 1;
      }
      std::printf("%-6s %-14s %8zu %9.3f (%8.3f) %9.3f (%8.3f) %10.2f %10.1f\n", layout, kindName(kind), one.contacts,
        one.minMs, one.medianMs, all.minMs, all.medianMs, one.minMs / all.minMs, bruteMs / all.minMs);
      std::snprintf(cell, sizeof(cell), "| %s | %zu | %s | %zu | %.3f (%.3f) | %.3f (%.3f) | %.2f | %.1f |\n", layout,
        scene.geometry.rest.size(), kindName(kind), one.contacts, one.minMs, one.medianMs, all.minMs, all.medianMs,
        one.minMs / all.minMs, bruteMs / all.minMs);
      table << cell;
      record("5.1", layout, scene.geometry.rest.size(), kind, 1, one);
      record("5.1", layout, scene.geometry.rest.size(), kind, maxThreads, all);
    }
  }

  // 2. Figure 5.2, extended.
  const std::vector<std::size_t> sizes = options.smoke
    ? std::vector<std::size_t>{ 500, 2000 }
    : std::vector<std::size_t>{ 500, 1000, 2000, 5000, 10000, 20000, 100000, 1000000 };
  const double bandwidth = bench::measureTriadBandwidth(options.smoke ? (1u << 21) : (1u << 24), 5);
  // Read once per point: start and predicted positions, radius, body; written once per contact.
  const auto boundMs = [&](std::size_t points, std::size_t contacts) {
    const double bytes = static_cast<double>(points) * (2 * sizeof(Vec3) + sizeof(double) + sizeof(std::int32_t)) +
      static_cast<double>(contacts) * sizeof(Contact);
    return 1e3 * bytes / bandwidth;
  };
  std::printf("\nFigure 5.2: uniform grid, box of particles, ms per detection (triad bandwidth %.1f GB/s at %zu threads)\n",
    bandwidth * 1e-9, maxThreads);
  std::printf("%10s %10s %20s %20s %10s %14s %12s %10s %8s\n", "particles", "contacts", "1 thread", "all threads", "speed-up", "ns/particle",
    "1thr CPU ms", "bound ms", "x bound");
  table << "\n## Figure 5.2\n\nThe uniform grid on a box of particles, minimum (median) of " << 5 * repeat
        << " runs (" << std::max(2, repeat / 2) << " at 10^6), and the slowest run at " << maxThreads << " threads, ms per detection; bound: its inputs read and its contacts written once at the"
        << " triad bandwidth measured in the same run (" << std::fixed << std::setprecision(1) << bandwidth * 1e-9
        << std::defaultfloat << std::setprecision(6) << " GB/s)\n\n"
        << "| particles | contacts | 1 thread | " << maxThreads << " threads | slowest at " << maxThreads
        << " threads | speed-up | ns per particle (" << maxThreads
        << " threads) | bound ms | x bound |\n|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (std::size_t n : sizes)
  {
    const ParticleScene scene = particleScene(n, false);
    // Five times the runs below 10^6: "at most 5 ms in every run" is a bound on the
    // slowest, which needs more runs than the minimum does.
    const int runs = n >= 1000000 ? std::max(2, repeat / 2) : 5 * repeat;
    const Timing one = timeDetection(scene, BroadPhase::UniformGrid, 1, runs);
    const Timing all = timeDetection(scene, BroadPhase::UniformGrid, maxThreads, runs);
    const double bound = boundMs(scene.geometry.rest.size(), all.contacts);
    std::printf("%10zu %10zu %9.3f (%8.3f) %9.3f (%8.3f) %10.2f %14.1f %12.3f %10.3f %8.1f\n", scene.geometry.rest.size(), one.contacts,
      one.minMs, one.medianMs, all.minMs, all.medianMs, one.minMs / all.minMs,
      1e6 * all.minMs / static_cast<double>(scene.geometry.rest.size()), one.cpuMs, bound, all.minMs / bound);
    std::snprintf(cell, sizeof(cell), "| %zu | %zu | %.3f (%.3f) | %.3f (%.3f) | %.3f | %.2f | %.1f | %.3f | %.1f |\n",
      scene.geometry.rest.size(), one.contacts, one.minMs, one.medianMs, all.minMs, all.medianMs, all.maxMs, one.minMs / all.minMs,
      1e6 * all.minMs / static_cast<double>(scene.geometry.rest.size()), bound, all.minMs / bound);
    table << cell;
    record("5.2", "box", scene.geometry.rest.size(), BroadPhase::UniformGrid, 1, one);
    record("5.2", "box", scene.geometry.rest.size(), BroadPhase::UniformGrid, maxThreads, all);
  }

  // 3. The Automatic crossover, at all threads.
  std::printf("\nAutomatic: brute force against the uniform grid on small scenes (all threads)\n");
  std::printf("%10s %14s %12s %12s %10s\n", "particles", "pair tests", "brute ms", "grid ms", "brute/grid");
  for (std::size_t n : options.smoke ? std::vector<std::size_t>{ 27, 125 } : std::vector<std::size_t>{ 8, 27, 64, 125, 216, 343, 512, 1000 })
  {
    const ParticleScene scene = particleScene(n, false);
    const Timing brute = timeDetection(scene, BroadPhase::BruteForce, maxThreads, repeat * 4);
    const Timing grid = timeDetection(scene, BroadPhase::UniformGrid, maxThreads, repeat * 4);
    const double points = static_cast<double>(scene.geometry.rest.size());
    std::printf("%10zu %14.0f %12.4f %12.4f %10.2f\n", scene.geometry.rest.size(), points * points, brute.minMs, grid.minMs,
      brute.minMs / grid.minMs);
    record("automatic", "box", scene.geometry.rest.size(), BroadPhase::BruteForce, maxThreads, brute);
    record("automatic", "box", scene.geometry.rest.size(), BroadPhase::UniformGrid, maxThreads, grid);
  }
  std::printf("\nCSV: %s\n", options.csv.c_str());
  return 0;
}
