// Mass-spring step cost on meshes from ~1k to ~150k tets, at 1 thread and at all threads.
//
// For each mesh and thread count it prints ms per step, tets per second, the speed-up over one
// thread, and the ratio of the measured step time to a memory-bandwidth bound: the bytes a step
// must move at least (modelled below from the data layout) divided by the triad bandwidth the
// same process measures with the same thread count. A ratio near 1 means the step runs at the
// speed of memory; far above 1 means compute or latency bound. A hash of the final state shows
// that every thread count computed the same thing. Results also go to CSV.
//
// Usage: bench_mass_spring [--smoke] [--data <shared data dir>] [--csv <file>]
#include "bench_meshes.h"
#include "bench_options.h"
#include "memory_bandwidth.h"

#include "softbody/common/errors.h"
#include "softbody/massspring/mass_spring_simulation.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <string>

using namespace softbody;

namespace
{
/// Least bytes one Euler-Cromer step moves through memory with core's layout (doubles,
/// int32 indices), counting each array once per pass that streams it:
///   spring pass   per edge: 2 indices, l0, k, k_d, the force written            56 B
///   volume pass   per tet: 4 indices, V0, k', k_d', the scale written           48 B
///   gather        per edge end: item + edge + force (36 B); per tet corner:
///                 item + scale + tet (28 B); per vertex: offsets, force out (32 B)
///   accel + integrate + floor, per vertex: x, v read and written, a, w         176 B
///   positions and velocities read by each element pass, per vertex              96 B
double modelledBytesPerStep(std::size_t vertices, std::size_t edges, std::size_t tets)
{
  return 56.0 * double(edges) + 48.0 * double(tets) + 36.0 * 2.0 * double(edges) +
    28.0 * 4.0 * double(tets) + (32.0 + 176.0 + 96.0) * double(vertices);
}

struct Measurement
{
  double secondsPerStep = 0.0;
  std::uint64_t hash = 0;
};

/// Times `steps` steps (0: choose a count worth ~0.3 s from a short probe, returned in
/// `steps`). Every thread count must run the same number of steps for the hashes to compare.
Measurement measure(const TetMesh& mesh, bool smoke, int& steps)
{
  BodyDescription body;
  body.mesh = mesh;
  double lowest = 1e300;
  for (const Vec3& p : mesh.points)
  {
    lowest = std::min(lowest, p.z());
  }
  SceneSettings scene;
  scene.floorEnabled = true;
  scene.floor.origin = Vec3(0, 0, lowest - 1e-3);
  MassSpringSimulation sim(body, scene);
  const double h = sim.stepSize();
  sim.advance(10 * h); // warm-up: caches, TBB threads, page faults

  const auto probeStart = std::chrono::steady_clock::now();
  sim.advance(sim.time() + 5 * h);
  const double probe = std::chrono::duration<double>(std::chrono::steady_clock::now() - probeStart).count() / 5;
  if (steps == 0)
  {
    steps = smoke ? 5 : std::max(20, static_cast<int>(0.3 / probe));
  }
  const auto start = std::chrono::steady_clock::now();
  sim.advance(sim.time() + steps * h);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return { seconds / steps, bench::hashPositions(sim.positions()) };
}

} // namespace

int main(int argc, char** argv)
{
  const bench::Options options = bench::parseOptions(argc, argv, "bench_mass_spring", "bench_mass_spring.csv");
  const int maxThreads = tbb::info::default_concurrency();
  std::vector<int> threadCounts{ 1 };
  if (maxThreads > 1)
  {
    threadCounts.push_back(maxThreads);
  }

  std::vector<double> bandwidth;
  const std::size_t probeElements = options.smoke ? (1u << 20) : (1u << 24); // 3 x 128 MiB
  for (int threads : threadCounts)
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    bandwidth.push_back(bench::measureTriadBandwidth(probeElements, options.smoke ? 2 : 5));
    std::printf("triad bandwidth, %d thread(s): %.2f GB/s\n", threads, bandwidth.back() / 1e9);
  }

  const std::vector<bench::NamedMesh> meshes = bench::benchmarkMeshes(options.smoke, options.dataDir);

  std::ofstream csv(options.csv);
  csv << "mesh,vertices,edges,tets,threads,ms_per_step,tets_per_second,speedup,"
         "modelled_MB_per_step,bandwidth_GBps,time_over_bandwidth_bound,state_hash\n";
  std::printf("\n%-22s %8s %8s %3s %10s %12s %8s %10s %16s\n", "mesh", "tets", "verts", "thr",
    "ms/step", "tets/s", "speedup", "x bw bound", "hash");
  for (const auto& named : meshes)
  {
    double oneThread = 0.0;
    std::uint64_t firstHash = 0;
    int steps = 0;
    for (std::size_t k = 0; k < threadCounts.size(); ++k)
    {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threadCounts[k]);
      Measurement m;
      try
      {
        m = measure(named.mesh, options.smoke, steps);
      }
      catch (const std::exception& error)
      {
        std::printf("%-22s skipped: %s\n", named.name.c_str(), error.what());
        break;
      }
      const Topology topology = buildTopology(named.mesh.points.size(), named.mesh.tets);
      const double bytes = modelledBytesPerStep(named.mesh.points.size(), topology.edges.size(), named.mesh.tets.size());
      const double bound = bytes / bandwidth[k];
      if (k == 0)
      {
        oneThread = m.secondsPerStep;
        firstHash = m.hash;
      }
      const double tetsPerSecond = double(named.mesh.tets.size()) / m.secondsPerStep;
      std::printf("%-22s %8zu %8zu %3d %10.3f %12.3g %8.2f %10.2f %016llx%s\n", named.name.c_str(),
        named.mesh.tets.size(), named.mesh.points.size(), threadCounts[k], 1e3 * m.secondsPerStep,
        tetsPerSecond, oneThread / m.secondsPerStep, m.secondsPerStep / bound,
        static_cast<unsigned long long>(m.hash), m.hash == firstHash ? "" : "  HASH DIFFERS");
      csv << named.name << ',' << named.mesh.points.size() << ',' << topology.edges.size() << ','
          << named.mesh.tets.size() << ',' << threadCounts[k] << ',' << 1e3 * m.secondsPerStep << ','
          << tetsPerSecond << ',' << oneThread / m.secondsPerStep << ',' << bytes / 1e6 << ','
          << bandwidth[k] / 1e9 << ',' << m.secondsPerStep / bound << ',' << m.hash << '\n';
      if (m.hash != firstHash)
      {
        std::fprintf(stderr, "error: the state differs between thread counts\n");
        return 1;
      }
    }
  }
  if (options.smoke)
  {
    // The timed steps above are a few steps of free fall. The state hash must also cover the
    // floor and the strain limiter: the generated boxes land on the floor (kLandingTime), the
    // same hash at every thread count, and each stage shown to act.
    for (const auto& named : meshes)
    {
      if (named.name.rfind("box_", 0) != 0)
      {
        continue;
      }
      BodyDescription body;
      body.mesh = named.mesh;
      auto landed = [&](const SceneSettings& scene) {
        MassSpringSimulation sim(body, scene);
        sim.advance(bench::kLandingTime);
        return sim.positions();
      };
      std::vector<Vec3> reference;
      std::uint64_t firstHash = 0;
      for (int threads : threadCounts)
      {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        const std::vector<Vec3> positions = landed(bench::landingScene(named.mesh));
        const std::uint64_t hash = bench::hashPositions(positions);
        std::printf("landing %-14s %d thread(s): hash %016llx\n", named.name.c_str(), threads,
          static_cast<unsigned long long>(hash));
        if (reference.empty())
        {
          reference = positions;
          firstHash = hash;
        }
        else if (hash != firstHash)
        {
          std::fprintf(stderr, "error: the landing state differs between thread counts\n");
          return 1;
        }
      }
      const double byFloor = bench::maxDistance(landed(bench::landingScene(named.mesh, false)), reference);
      const double byLimit = bench::maxDistance(landed(bench::landingScene(named.mesh, true, 0.0)), reference);
      std::printf("landing %-14s without the floor: %.3g m away, without the limiter: %.3g m away\n",
        named.name.c_str(), byFloor, byLimit);
      if (!(byFloor > 1e-3 && byLimit > 1e-5))
      {
        std::fprintf(stderr, "error: the landing scene does not exercise the floor and the limiter\n");
        return 1;
      }
    }
  }
  std::printf("\nCSV written to %s\n", options.csv.c_str());
  return 0;
}
