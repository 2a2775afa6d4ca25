// Mass-spring step cost on boxes from ~1k to ~150k tets and on real meshes (the public tet
// meshes, TetGen meshes of the public surfaces and of a ~180k-tet ellipsoid), each with its
// vertices in input order, along a Morton curve and in reverse Cuthill-McKee order
// (mesh/reorder.h), at 1 thread and at all threads.
//
// For each mesh and thread count it prints ms per step, tets per second, the speed-up over one
// thread, and the ratio of the measured step time to a memory-bandwidth bound: the bytes a step
// must move at least (modelled below from the data layout) divided by the triad bandwidth the
// same process measures with the same thread count. A ratio near 1 means the step runs at the
// speed of memory; far above 1 means compute or latency bound. A hash of the final state shows
// that every thread count computed the same thing. Each row also gives its time over the same
// mesh in input order (the gain of reordering, measured in the same run) and its per-tet time
// over the largest box's in its generated order (same threads). Results also go to CSV.
//
// Then, per mesh in Morton order, an access probe: the force evaluation (both element passes
// and both gathers) against the same loops with the same index streams, loads and stores but
// no arithmetic (each loaded value summed into the stored one): how much of the evaluation the
// memory accesses alone take.
//
// Usage: bench_mass_spring [--smoke] [--data <shared data dir>] [--csv <file>]
//                          [--mesh <name or file>] [--repeat <timed runs per case>]
#include "bench_meshes.h"
#include "bench_options.h"
#include "memory_bandwidth.h"

#include "softbody/common/errors.h"
#include "softbody/common/parallel.h"
#include "softbody/massspring/mass_spring_forces.h"
#include "softbody/massspring/mass_spring_reordered.h"
#include "softbody/mesh/reorder.h"
#include "softbody/massspring/mass_spring_simulation.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <string>

using namespace softbody;

namespace
{
/// Least bytes one Euler-Cromer step moves through memory with core's layout (doubles,
/// int32 indices), counting each array once per pass that streams it:
///   spring pass   per edge: 2 indices, l0, k, k_d, the force written            56 B
///   volume pass   per tet: 4 indices, V0, k', k_d', the four corner forces
///                 written (ForceScratch::tetCornerForce)                        136 B
///   gather        per edge end: item + edge + force (36 B); per tet corner:
///                 item + corner force (28 B); per vertex: offsets, force out (32 B)
///   accel + integrate + floor, per vertex: x, v read and written, a, w         176 B
///   positions and velocities read by each element pass, per vertex              96 B
double modelledBytesPerStep(std::size_t vertices, std::size_t edges, std::size_t tets)
{
  return 56.0 * double(edges) + 136.0 * double(tets) + 36.0 * 2.0 * double(edges) +
    28.0 * 4.0 * double(tets) + (32.0 + 176.0 + 96.0) * double(vertices);
}

struct Measurement
{
  bench::MinMedian secondsPerStep;
  double cpuSecondsPerStep = 0.0; ///< least CPU time of the calling thread per step
  double setupSeconds = 0.0;
  std::uint64_t hash = 0;
};

/// Builds the stepper on the mesh renumbered by `ordering` and times `repeat` runs of `steps`
/// steps (0: choose a count worth ~0.3 s from a short probe, returned in `steps`). Every thread
/// count must run the same number of steps for the hashes to compare. The hash is of the
/// positions in input order.
Measurement measure(const TetMesh& mesh, VertexOrdering ordering, bool smoke, int repeat, int& steps)
{
  Body body;
  body.mesh = mesh;
  double lowest = 1e300;
  for (const Vec3& p : mesh.points)
  {
    lowest = std::min(lowest, p.z());
  }
  SceneSettings scene;
  scene.floorEnabled = true;
  scene.floor.origin = Vec3(0, 0, lowest - 1e-3);
  const auto setupStart = std::chrono::steady_clock::now();
  std::unique_ptr<Simulation> sim = makeMassSpringSimulation(body, scene, ordering);
  Measurement result;
  result.setupSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - setupStart).count();
  const double h = sim->stepSize();
  sim->advance(10 * h); // warm-up: caches, TBB threads, page faults

  const auto probeStart = std::chrono::steady_clock::now();
  sim->advance(sim->time() + 5 * h);
  const double probe = std::chrono::duration<double>(std::chrono::steady_clock::now() - probeStart).count() / 5;
  if (steps == 0)
  {
    steps = smoke ? 5 : std::max(20, static_cast<int>(0.3 / probe));
  }
  std::vector<double> perStep, cpuPerStep;
  for (int r = 0; r < repeat; ++r)
  {
    const auto start = std::chrono::steady_clock::now();
    const double cpuStart = bench::threadCpuSeconds();
    sim->advance(sim->time() + steps * h);
    cpuPerStep.push_back((bench::threadCpuSeconds() - cpuStart) / steps);
    perStep.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / steps);
  }
  result.secondsPerStep = bench::minMedian(perStep);
  result.cpuSecondsPerStep = bench::minMedian(cpuPerStep).min;
  result.hash = bench::hashPositions(sim->positions());
  return result;
}

/// The access probe (file comment): returns {force evaluation, accesses alone} in seconds.
std::pair<double, double> accessProbe(const TetMesh& mesh, int repeat)
{
  const Reordering reordering = computeReordering(VertexOrdering::Morton, mesh.points, mesh.tets, {}, true);
  const std::vector<Vec3> x = toStorageOrder(mesh.points, reordering.vertexOrder);
  const Topology topology = buildTopology(x.size(), reorderTets(mesh.tets, reordering));
  std::vector<std::string> warnings;
  const ElementConstants constants = computeElementConstants(topology, x, MaterialSettings{}, warnings);
  const std::vector<Vec3> v(x.size(), Vec3(0.01, -0.02, 0.03));
  ForceScratch scratch;
  std::vector<Vec3> forces;
  const double evaluation = bench::leastSecondsPerCall(repeat, 20, false, [&] {
    computeInternalForces(topology, constants, x, v, scratch, forces);
  });
  // The same loops (chunks, grains, index streams) with every value loaded once and summed.
  std::vector<Vec3> springForce(topology.edges.size()), cornerForce(4 * topology.tets.size()), sums(x.size());
  const double accesses = bench::leastSecondsPerCall(repeat, 20, false, [&] {
    parallelFor((topology.edges.size() + 2047) / 2048, 1, [&](std::size_t chunk) {
      for (std::size_t e = chunk * 2048; e < std::min(topology.edges.size(), chunk * 2048 + 2048); ++e)
      {
        const Edge& edge = topology.edges[e];
        springForce[e] = x[edge.a] + x[edge.b] + v[edge.a] + v[edge.b] +
          Vec3::Constant(constants.restLength[e] + constants.springStiffness[e] + constants.springDamping[e]);
      }
    });
    parallelFor((topology.tets.size() + 2047) / 2048, 1, [&](std::size_t chunk) {
      for (std::size_t t = chunk * 2048; t < std::min(topology.tets.size(), chunk * 2048 + 2048); ++t)
      {
        const Tet& tet = topology.tets[t];
        const Vec3 c = Vec3::Constant(constants.restVolume[t] + constants.volumeStiffness[t] + constants.volumeDamping[t]);
        for (int k = 0; k < 4; ++k)
        {
          cornerForce[4 * t + static_cast<std::size_t>(k)] = x[tet[k]] + v[tet[k]] + c;
        }
      }
    });
    parallelFor(x.size(), 1024, [&](std::size_t i) {
      Vec3 sum = Vec3::Zero();
      for (std::int32_t k = topology.vertexEdges.offsets[i]; k < topology.vertexEdges.offsets[i + 1]; ++k)
      {
        const std::int32_t e = topology.vertexEdges.items[k];
        sum += (topology.edges[e].a == static_cast<std::int32_t>(i)) ? springForce[e] : Vec3(-springForce[e]);
      }
      sums[i] = sum;
    });
    parallelFor(x.size(), 1024, [&](std::size_t i) {
      Vec3 sum = sums[i];
      for (std::int32_t k = topology.vertexTetCorners.offsets[i]; k < topology.vertexTetCorners.offsets[i + 1]; ++k)
      {
        sum += cornerForce[static_cast<std::size_t>(topology.vertexTetCorners.items[k])];
      }
      sums[i] = sum;
    });
  });
  return { evaluation, accesses };
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
    std::printf("triad bandwidth, %d thread(s): %.2f GB/s; cores this process gets (compute "
                "probe): %.2f\n", threads, bandwidth.back() / 1e9,
      bench::measureComputeParallelism(options.smoke ? 1 : 5));
  }

  const std::vector<bench::NamedMesh> meshes =
    bench::benchmarkMeshes(options.smoke, options.dataDir, options.mesh);
  const bench::NamedMesh* box = bench::referenceBox(meshes);
  const std::vector<VertexOrdering> orderings = { VertexOrdering::Input, VertexOrdering::Morton,
    VertexOrdering::ReverseCuthillMcKee };
  // Seconds per tet-step of the reference box in its generated order (already perfectly
  // local), per thread count: every row is compared with it ("x box": its per-tet time over the
  // box's at the same thread count).
  std::map<int, double> boxPerTet;

  std::ofstream csv(options.csv);
  // The same rows as a table for docs/performance.md (scripts/update_docs_tables.py).
  std::ofstream table(bench::tableBeside(options.csv));
  // One row per mesh and thread count, in the filter's order (Morton), beside input order.
  table << "| mesh | tets | points | threads | ms/step, input order | ms/step, Morton | Morton over input | "
           "speed-up | x bw bound | per tet over the box |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  csv << "mesh,vertices,edges,tets,ordering,threads,ms_per_step,ms_per_step_median,cpu_ms_per_step,setup_ms,"
         "tets_per_second,speedup,modelled_MB_per_step,bandwidth_GBps,time_over_bandwidth_bound,"
         "time_over_input_order,per_tet_time_over_box,state_hash\n";
  std::printf("\nms/step: minimum (median) of %d run(s), wall time; 'cpu ms': least CPU time of "
              "the calling thread per step (1 thread only; leaves out time other processes held "
              "the core); 'x bw': time over the bandwidth bound; "
              "'/input': time over the same mesh in input order; 'x box': per-tet time over %s's in input order\n",
    options.repeat, box ? box->name.c_str() : "(no box)");
  std::printf("%-22s %7s %6s %-6s %3s %9s %9s %8s %8s %10s %7s %6s %6s %6s %16s\n", "mesh", "tets",
    "verts", "order", "thr", "ms/step", "(median)", "cpu ms", "setup ms", "tets/s", "speedup",
    "x bw", "/input", "x box", "hash");
  for (const auto& named : meshes)
  {
    const Topology topology = buildTopology(named.mesh.points.size(), named.mesh.tets);
    const double bytes = modelledBytesPerStep(named.mesh.points.size(), topology.edges.size(), named.mesh.tets.size());
    const double tets = double(named.mesh.tets.size());
    int steps = 0;
    std::map<int, double> inputOrder; // threads -> s/step in input order
    for (VertexOrdering ordering : orderings)
    {
      double oneThread = 0.0;
      std::uint64_t firstHash = 0;
      for (std::size_t k = 0; k < threadCounts.size(); ++k)
      {
        const int threads = threadCounts[k];
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        Measurement m;
        try
        {
          m = measure(named.mesh, ordering, options.smoke, options.repeat, steps);
        }
        catch (const std::exception& error)
        {
          std::printf("%-22s skipped: %s\n", named.name.c_str(), error.what());
          break;
        }
        const double t = m.secondsPerStep.min;
        const double bound = bytes / bandwidth[k];
        if (k == 0)
        {
          oneThread = t;
          firstHash = m.hash;
        }
        if (ordering == VertexOrdering::Input)
        {
          inputOrder[threads] = t;
        }
        if (box == &named && ordering == VertexOrdering::Input)
        {
          boxPerTet[threads] = t / tets;
        }
        const double overInput = inputOrder.count(threads) ? t / inputOrder[threads] : 0.0;
        const double overBox = boxPerTet.count(threads) ? (t / tets) / boxPerTet[threads] : 0.0;
        std::printf("%-22s %7zu %6zu %-6s %3d %9.3f %9.3f %8.3f %8.1f %10.3g %7.2f %6.2f %6.2f %6.2f %016llx%s\n",
          named.name.c_str(), named.mesh.tets.size(), named.mesh.points.size(),
          vertexOrderingName(ordering), threads, 1e3 * t, 1e3 * m.secondsPerStep.median,
          threads == 1 ? 1e3 * m.cpuSecondsPerStep : 0.0, 1e3 * m.setupSeconds, tets / t, oneThread / t, t / bound, overInput, overBox,
          static_cast<unsigned long long>(m.hash), m.hash == firstHash ? "" : "  HASH DIFFERS");
        if (ordering == kDefaultVertexOrdering)
        {
          char overTheBox[32] = "-"; // the boxes measured before the reference box
          if (overBox > 0.0)
          {
            std::snprintf(overTheBox, sizeof overTheBox, "%.2f", overBox);
          }
          char row[256];
          std::snprintf(row, sizeof row, "| %s | %zu | %zu | %d | %.3g | %.3g | %.2f | %.2f | %.2f | %s |\n",
            named.name.c_str(), named.mesh.tets.size(), named.mesh.points.size(), threads,
            1e3 * inputOrder[threads], 1e3 * t, overInput, oneThread / t, t / bound, overTheBox);
          table << row;
        }
        csv << named.name << ',' << named.mesh.points.size() << ',' << topology.edges.size() << ','
            << named.mesh.tets.size() << ',' << vertexOrderingName(ordering) << ',' << threads << ','
            << 1e3 * t << ',' << 1e3 * m.secondsPerStep.median << ',' << 1e3 * m.cpuSecondsPerStep << ','
            << 1e3 * m.setupSeconds << ','
            << tets / t << ',' << oneThread / t << ',' << bytes / 1e6 << ',' << bandwidth[k] / 1e9
            << ',' << t / bound << ',' << overInput << ',' << overBox << ',' << m.hash << '\n';
        if (m.hash != firstHash)
        {
          std::fprintf(stderr, "error: the state differs between thread counts\n");
          return 1;
        }
      }
    }
  }
  std::printf("\nAccess probe, Morton order: ms per force evaluation against the same loops doing "
              "only their loads and stores (no arithmetic), least of %d\n", options.repeat);
  for (const auto& named : meshes)
  {
    for (int threads : threadCounts)
    {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      const auto [evaluation, accesses] = accessProbe(named.mesh, options.smoke ? 1 : options.repeat);
      std::printf("%-22s %d thread(s): evaluation %.3f ms, accesses alone %.3f ms (%.0f %%)\n", named.name.c_str(),
        threads, 1e3 * evaluation, 1e3 * accesses, 100.0 * accesses / evaluation);
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
      Body body;
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
