// The wide (four-lane) kernels against the one-at-a-time kernels, on each mesh renumbered along a
// Morton curve, measured in the same run:
//   - XPBD: one iteration of links + tet volumes swept color by color (the parallel
//     Gauss-Seidel solver's storage), per constraint ('scalar'), with the wide kernels at the
//     baseline level (SSE2: two doubles per instruction) and at AVX2 (four); sequential
//     Gauss-Seidel over the batches stored as PbdSimulation stores them for it (sorted by
//     vertex, then interleaved in four streams: pbd_solvers.h, interleavedStreams), one
//     constraint at a time ('sequential') and with the wide kernels on the blocks of four that
//     share no particle ('seq wide', the solver's path; same bits); the wide colored sweep at
//     all threads;
//   - mass-spring: the internal forces (both element passes and the per-vertex gather) at each
//     level, and at all threads.
// 1-thread times are the calling thread's CPU time (min of --repeat runs; other processes
// compiling on a shared machine do not count), all-thread times are wall time. Each row also
// checks that the scalar and every wide colored sweep end in the same bits, and the two
// sequential ones. 'x bw' is the time over the constraint data an iteration streams at least
// (indices, rest value, the two per-step constants, multiplier read and written, broken flag:
// 49 B per link, 57 B per tet), at the triad bandwidth this process measures.
// The all-thread columns hold only when no other process wants the other cores: the colored
// sweep starts one parallel loop per color (about 60 per iteration on a TetGen mesh), and a
// competing process, even at nice 19, can keep a worker off its core for a whole loop so the
// calling thread runs the worker's half too (measured on the 2-core machine: 1.0x, down to
// 0.64x, instead of 2.0x idle). 'cores' is the compute probe run right before the all-thread
// timings (memory_bandwidth.h): the rows whose value is well under the thread count were
// measured on a shared machine.
//
// With --csv FILE the rows go to FILE and, as a Markdown table, to FILE's .md sibling
// (docs/performance.md's table, scripts/update_docs_tables.py).
//
// Usage: bench_wide_kernels [--smoke] [--data <shared data dir>] [--mesh <name or file>]
//                           [--repeat <timed runs>] [--csv <file>]
#include "bench_meshes.h"
#include "bench_options.h"
#include "memory_bandwidth.h"

#include "softbody/common/simd.h"
#include "softbody/massspring/mass_spring_forces.h"
#include "softbody/mesh/graph_coloring.h"
#include "softbody/mesh/reorder.h"
#include "softbody/mesh/topology.h"
#include "softbody/pbd/pbd_solvers.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <string>
#include <numeric>
#include <random>

using namespace softbody;

namespace
{

struct BatchedBody
{
  std::vector<Vec3> x;
  std::vector<double> w;
  DistanceBatch links;
  VolumeBatch volumes;
  BatchSchedule linkSchedule, volumeSchedule;
  DistanceBatch sequentialLinks; ///< the same constraints in sequential Gauss-Seidel's order
  VolumeBatch sequentialVolumes;
  std::vector<char> linkBlocks, volumeBlocks; ///< their independent blocks of four
};

/// XPBD batches of the mesh stored color by color, compliant (alphaTilde of a soft rubber at a
/// 1 ms step), positions jittered by 1% of the mean edge so every constraint has work.
BatchedBody makeBody(const std::vector<Vec3>& points, const Topology& topology)
{
  BatchedBody body;
  body.w.assign(points.size(), 1.0);
  double meanEdge = 0.0;
  for (const Edge& e : topology.edges)
  {
    meanEdge += (points[e.a] - points[e.b]).norm();
    body.links.ends.push_back({ e.a, e.b });
    body.links.rest.push_back((points[e.a] - points[e.b]).norm());
  }
  meanEdge /= double(topology.edges.size());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.01 * meanEdge, 0.01 * meanEdge);
  body.x = points;
  for (Vec3& p : body.x)
  {
    p += Vec3(u(rng), u(rng), u(rng));
  }
  ProjectionParameters p;
  p.scale = 1.0;
  p.alphaTilde = 1e-2;
  body.links.broken.assign(body.links.ends.size(), 0);
  body.links.lambda.assign(body.links.ends.size(), 0.0);
  body.links.params.assign(body.links.ends.size(), p);
  for (const Tet& t : topology.tets)
  {
    body.volumes.tets.push_back(t);
    body.volumes.restVolume.push_back(signedTetVolume(points[t[0]], points[t[1]], points[t[2]], points[t[3]]));
  }
  body.volumes.broken.assign(body.volumes.tets.size(), 0);
  body.volumes.lambda.assign(body.volumes.tets.size(), 0.0);
  body.volumes.params.assign(body.volumes.tets.size(), p);
  body.sequentialLinks = body.links;
  body.sequentialVolumes = body.volumes;
  body.sequentialLinks.storeInOrder(interleavedStreams(body.links.size()));
  body.sequentialVolumes.storeInOrder(interleavedStreams(body.volumes.size()));
  body.linkBlocks = independentBlocks(body.sequentialLinks);
  body.volumeBlocks = independentBlocks(body.sequentialVolumes);
  const std::vector<char> movable(points.size(), 1);
  auto store = [&](auto& batch, BatchSchedule& schedule) {
    schedule.coloring = colorConstraints(points.size(), flattenParticles(batch), std::decay_t<decltype(batch)>::Arity, movable);
    batch.storeInOrder(schedule.coloring.order);
    std::iota(schedule.coloring.order.begin(), schedule.coloring.order.end(), 0);
  };
  store(body.links, body.linkSchedule);
  store(body.volumes, body.volumeSchedule);
  return body;
}

enum class Sweep
{
  Scalar,
  WideBaseline,
  WideAvx2,
  Sequential,
  SequentialWide
};

void iterate(BatchedBody& body, Sweep sweep)
{
  if (sweep == Sweep::SequentialWide)
  {
    gaussSeidelLinksWide(body.sequentialLinks, body.linkBlocks, body.x, body.w);
    gaussSeidelVolumesWide(body.sequentialVolumes, body.volumeBlocks, body.x, body.w);
    return;
  }
  if (sweep == Sweep::Sequential)
  {
    gaussSeidelSweep(body.sequentialLinks, body.x, body.w);
    gaussSeidelSweep(body.sequentialVolumes, body.x, body.w);
    return;
  }
  if (sweep == Sweep::Scalar)
  {
    body.linkSchedule.storedByColor = body.volumeSchedule.storedByColor = false;
    coloredGaussSeidelSweep(body.links, body.linkSchedule, body.x, body.w);
    coloredGaussSeidelSweep(body.volumes, body.volumeSchedule, body.x, body.w);
    return;
  }
  const SimdLevel level = sweep == Sweep::WideAvx2 ? SimdLevel::Avx2 : SimdLevel::Baseline;
  for (const auto* schedule : { &body.linkSchedule, &body.volumeSchedule })
  {
    const Coloring& coloring = schedule->coloring;
    for (std::size_t color = 0; color < coloring.colorCount(); ++color)
    {
      const auto begin = static_cast<std::size_t>(coloring.colorOffsets[color]);
      const auto end = static_cast<std::size_t>(coloring.colorOffsets[color + 1]);
      if (schedule == &body.linkSchedule)
      {
        projectLinksWide(body.links, begin, end, body.x, body.w, level);
      }
      else
      {
        projectVolumesWide(body.volumes, begin, end, body.x, body.w, level);
      }
    }
  }
}

/// One mesh's XPBD iteration: seconds per iteration of each Sweep (1 thread), of the wide
/// colored sweep at all threads, the best wide sweep's time over its streaming bound, and the
/// cores the process got right before the all-thread timing.
struct SweepRow
{
  std::string name;
  std::size_t tets, links;
  double seconds[5], threaded, overBound, cores;
};

/// One mesh's mass-spring internal forces, seconds per evaluation.
struct ForceRow
{
  std::string name;
  double baseline, avx2, threads, cores;
};

/// Milliseconds with three decimals, or "-" for a level this CPU does not have.
std::string milliseconds(double seconds, bool measured)
{
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", 1e3 * seconds);
  return measured ? text : "-";
}

/// The rows as CSV and, beside it, as the Markdown table of docs/performance.md.
void writeTables(const std::string& path, const std::vector<SweepRow>& sweeps,
  const std::vector<ForceRow>& forces, int threads, bool avx2)
{
  std::ofstream csv(path);
  csv << "mesh,tets,links,scalar_ms,wide_baseline_ms,wide_avx2_ms,sequential_ms,sequential_wide_ms,"
         "wide_threads_ms,threads,time_over_bandwidth_bound,cores,forces_baseline_ms,forces_avx2_ms,"
         "forces_threads_ms\n";
  std::ofstream table(bench::tableBeside(path));
  table << "| mesh | tets | links | scalar colored | wide, baseline | wide, AVX2 | sequential GS | seq wide "
           "| wide, " << threads << " thr | scalar over wide | 1 / " << threads << " thr | x bw | cores "
           "| forces, baseline | forces, AVX2 | forces, " << threads << " thr |\n"
           "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  char line[512];
  for (std::size_t i = 0; i < sweeps.size(); ++i)
  {
    const SweepRow& s = sweeps[i];
    const ForceRow& f = forces[i];
    const double best = avx2 ? s.seconds[int(Sweep::WideAvx2)] : s.seconds[int(Sweep::WideBaseline)];
    csv << s.name << ',' << s.tets << ',' << s.links;
    for (double t : s.seconds)
    {
      csv << ',' << 1e3 * t;
    }
    csv << ',' << 1e3 * s.threaded << ',' << threads << ',' << s.overBound << ',' << s.cores << ','
        << 1e3 * f.baseline << ',' << 1e3 * f.avx2 << ',' << 1e3 * f.threads << '\n';
    std::snprintf(line, sizeof line,
      "| %s | %zu | %zu | %.3f | %.3f | %s | %.3f | %.3f | %.3f | %.2f | %.2f | %.2f | %.2f | %.3f | %s | %.3f |\n",
      s.name.c_str(), s.tets, s.links, 1e3 * s.seconds[0], 1e3 * s.seconds[1],
      milliseconds(s.seconds[2], avx2).c_str(), 1e3 * s.seconds[3], 1e3 * s.seconds[4], 1e3 * s.threaded,
      s.seconds[0] / best, best / s.threaded, s.overBound, s.cores, 1e3 * f.baseline,
      milliseconds(f.avx2, avx2).c_str(), 1e3 * f.threads);
    table << line;
  }
}

} // namespace

int main(int argc, char** argv)
{
  const bench::Options options = bench::parseOptions(argc, argv, "bench_wide_kernels", "");
  const int repeat = options.smoke ? 1 : std::max(options.repeat, 3);
  const int calls = options.smoke ? 1 : 5;
  const int maxThreads = tbb::info::default_concurrency();
  const bool avx2 = bestSimdLevel() == SimdLevel::Avx2;
  double bandwidth = 0.0;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    bandwidth = bench::measureTriadBandwidth(options.smoke ? 1u << 20 : 1u << 25, options.smoke ? 1 : 5);
  }
  const double bandwidthAll = bench::measureTriadBandwidth(options.smoke ? 1u << 20 : 1u << 25, options.smoke ? 1 : 5);
  std::printf("best SIMD level of this CPU: %s; triad bandwidth, 1 thread: %.2f GB/s, %d threads: %.2f GB/s\n",
    simdLevelName(bestSimdLevel()), 1e-9 * bandwidth, maxThreads, 1e-9 * bandwidthAll);
  std::printf("XPBD, ms per iteration (links + tet volumes), Morton order; 1 thread: least CPU ms of %d runs; "
              "%d thr: wall ms\n", repeat, maxThreads);
  std::printf("%-24s %8s %8s %9s %9s %9s %10s %9s %9s %7s %7s %6s %5s %s\n", "mesh", "tets", "links", "scalar", "baseline",
    "wide AVX2", "sequential", "seq wide", "wide Nthr", "scal/w", "1/Nthr", "x bw", "cores", "bits");
  const std::vector<bench::NamedMesh> meshes = bench::benchmarkMeshes(options.smoke, options.dataDir, options.mesh);
  std::vector<ForceRow> forceRows;
  std::vector<SweepRow> sweepRows;
  for (const bench::NamedMesh& named : meshes)
  {
    const Reordering reordering =
      computeReordering(VertexOrdering::Morton, named.mesh.points, named.mesh.tets, {}, true);
    const std::vector<Vec3> points = toStorageOrder(named.mesh.points, reordering.vertexOrder);
    const Topology topology = buildTopology(points.size(), reorderTets(named.mesh.tets, reordering));
    const BatchedBody start = makeBody(points, topology);

    double seconds[5] = { 0, 0, 0, 0, 0 };
    std::vector<Vec3> after[5];
    for (Sweep sweep : { Sweep::Scalar, Sweep::WideBaseline, Sweep::WideAvx2, Sweep::Sequential, Sweep::SequentialWide })
    {
      if (sweep == Sweep::WideAvx2 && !avx2)
      {
        continue;
      }
      tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
      BatchedBody body = start;
      seconds[int(sweep)] = bench::leastSecondsPerCall(repeat, calls, true, [&] { iterate(body, sweep); });
      BatchedBody check = start;
      iterate(check, sweep);
      after[int(sweep)] = check.x;
    }
    const double cores = bench::measureComputeParallelism(options.smoke ? 1 : 3);
    BatchedBody parallel = start;
    parallel.linkSchedule.storedByColor = parallel.volumeSchedule.storedByColor = true;
    const double threaded = bench::leastSecondsPerCall(repeat, calls, false, [&] {
      coloredGaussSeidelSweep(parallel.links, parallel.linkSchedule, parallel.x, parallel.w);
      coloredGaussSeidelSweep(parallel.volumes, parallel.volumeSchedule, parallel.x, parallel.w);
    });
    const int best = avx2 ? int(Sweep::WideAvx2) : int(Sweep::WideBaseline);
    const bool same = std::memcmp(after[0].data(), after[1].data(), after[0].size() * sizeof(Vec3)) == 0 &&
      (!avx2 || std::memcmp(after[0].data(), after[2].data(), after[0].size() * sizeof(Vec3)) == 0) &&
      std::memcmp(after[3].data(), after[4].data(), after[3].size() * sizeof(Vec3)) == 0;
    const double bytes = 49.0 * double(topology.edges.size()) + 57.0 * double(topology.tets.size());
    std::printf("%-24s %8zu %8zu %9.3f %9.3f %9.3f %10.3f %9.3f %9.3f %7.2f %7.2f %6.2f %5.2f %s\n", named.name.c_str(),
      topology.tets.size(), topology.edges.size(), 1e3 * seconds[0], 1e3 * seconds[1], 1e3 * seconds[2],
      1e3 * seconds[3], 1e3 * seconds[4], 1e3 * threaded, seconds[0] / seconds[best], seconds[best] / threaded,
      seconds[best] / (bytes / bandwidth), cores, same ? "equal" : "DIFFER");
    if (!same)
    {
      return 1;
    }
    sweepRows.push_back({ named.name, topology.tets.size(), topology.edges.size(),
      { seconds[0], seconds[1], seconds[2], seconds[3], seconds[4] }, threaded,
      seconds[best] / (bytes / bandwidth), cores });

    // Mass-spring forces at each level.
    std::vector<std::string> warnings;
    const ElementConstants constants = computeElementConstants(topology, points, MaterialSettings{}, warnings);
    const std::vector<Vec3> v(points.size(), Vec3(0.01, -0.02, 0.03));
    ForceScratch scratch;
    std::vector<Vec3> forces;
    ForceRow row{ named.name, 0, 0, 0, 0 };
    {
      tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
      row.baseline = bench::leastSecondsPerCall(repeat, calls, true, [&] {
        computeInternalForces(topology, constants, start.x, v, scratch, forces, SimdLevel::Baseline);
      });
      if (avx2)
      {
        row.avx2 = bench::leastSecondsPerCall(repeat, calls, true, [&] {
          computeInternalForces(topology, constants, start.x, v, scratch, forces, SimdLevel::Avx2);
        });
      }
    }
    row.cores = bench::measureComputeParallelism(options.smoke ? 1 : 3);
    row.threads = bench::leastSecondsPerCall(repeat, calls, false,
      [&] { computeInternalForces(topology, constants, start.x, v, scratch, forces); });
    forceRows.push_back(row);
  }
  std::printf("\nMass-spring internal forces (element passes + gather), ms per evaluation, Morton order\n");
  std::printf("%-24s %10s %10s %10s %8s %6s\n", "mesh", "base 1thr", "AVX2 1thr", "best Nthr", "1/Nthr", "cores");
  for (const ForceRow& r : forceRows)
  {
    const double best = avx2 ? r.avx2 : r.baseline;
    std::printf("%-24s %10.3f %10.3f %10.3f %8.2f %6.2f\n", r.name.c_str(), 1e3 * r.baseline, 1e3 * r.avx2,
      1e3 * r.threads, best / r.threads, r.cores);
  }
  if (!options.csv.empty())
  {
    writeTables(options.csv, sweepRows, forceRows, maxThreads, avx2);
    std::printf("\nCSV: %s, table: %s\n", options.csv.c_str(), bench::tableBeside(options.csv).c_str());
  }
  return 0;
}
