// PBD/XPBD solvers: convergence against iterations and against time, and projection throughput.
//
// 1. The PBD thesis's Figures 5.3 and 5.4: a 50 x 50 and a 100 x 100 cloth stretched 16 times
//    and released (no gravity, PBD stiffness 1), one step of N iterations, the residual after
//    each iteration, for Gauss-Seidel, SOR at several factors, averaged Jacobi and parallel
//    (colored) Gauss-Seidel at 1 and all threads. Time per iteration is the solver's own stage
//    time (the residual evaluation is timed apart), so "residual against time" is what a user
//    pays. Written as CSV; tests/bench/plot_pbd_convergence.py draws the PNG.
// 2. XPBD throughput on the benchmark tet meshes (boxes, the public tet meshes, TetGen meshes of
//    the public surfaces and of a ~180k-tet ellipsoid), with the particles in input order,
//    along a Morton curve and in reverse Cuthill-McKee order: constraint projections (edges +
//    tets) per second per thread, the speed-up from 1 to all threads, the time over input order
//    and over the largest box (per projection), and a state hash showing both thread counts
//    computed the same thing.
//
// Each CSV has a Markdown table beside it (<prefix>_convergence.md, <prefix>_throughput.md in
// the filter's Morton order) for docs/performance.md (scripts/update_docs_tables.py).
//
// Usage: bench_pbd [--smoke] [--data <shared data dir>] [--csv <prefix>]
//                  [--mesh <name or file>] [--repeat <timed runs per case>]
#include "bench_meshes.h"
#include "scenes/stretched_cloth.h"
#include "bench_options.h"
#include "memory_bandwidth.h"

#include "softbody/pbd/cloth.h"
#include "softbody/pbd/pbd_reordered.h"
#include "softbody/pbd/pbd_simulation.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <string>

using namespace softbody;

namespace
{
/// Time spent projecting constraints (every solve stage of the plan), residual excluded.
double solveSeconds(const PbdSimulation& sim)
{
  const StepPlan& plan = sim.stepPlan();
  double seconds = 0.0;
  for (Stage stage : { Stage::SolveLinks, Stage::SolveTetElasticity, Stage::SolveVolumes, Stage::SolveAttachments, Stage::SolveContacts })
  {
    seconds += plan.runs(stage) ? plan.seconds(stage) : 0.0;
  }
  return seconds;
}

struct SolverCase
{
  std::string name;
  PbdSolver solver;
  double relaxation;
  int threads;
};

void convergence(const bench::Options& options, int maxThreads)
{
  std::ofstream csv(options.csv + "_convergence.csv");
  csv << "cloth,solver,threads,iteration,residual,seconds\n";
  std::ofstream table(bench::tableBeside(options.csv + "_convergence.csv"));
  const int iterations = options.smoke ? 10 : 200;
  table << "| cloth | solver | threads | residual after 10 | after 50 | after " << iterations
        << " | ms / iteration |\n|---|---|---:|---:|---:|---:|---:|\n";
  std::vector<SolverCase> cases = { { "Gauss-Seidel", PbdSolver::GaussSeidel, 1.0, 1 },
    { "SOR 1.2", PbdSolver::GaussSeidel, 1.2, 1 }, { "SOR 1.5", PbdSolver::GaussSeidel, 1.5, 1 },
    { "SOR 1.8", PbdSolver::GaussSeidel, 1.8, 1 }, { "Jacobi", PbdSolver::Jacobi, 1.0, 1 },
    { "Jacobi", PbdSolver::Jacobi, 1.0, maxThreads },
    { "Parallel Gauss-Seidel", PbdSolver::ParallelGaussSeidel, 1.0, 1 },
    { "Parallel Gauss-Seidel", PbdSolver::ParallelGaussSeidel, 1.0, maxThreads } };
  const std::vector<int> sizes = options.smoke ? std::vector<int>{ 20 } : std::vector<int>{ 50, 100 };
  for (int n : sizes)
  {
    std::printf("\n%d x %d cloth stretched 16x, %d iterations of one step (PBD, k = 1)\n", n, n, iterations);
    std::printf("%-24s %3s %12s %12s %12s %14s\n", "solver", "thr", "r(10)", "r(50)", "r(last)", "ms/iteration");
    for (const SolverCase& c : cases)
    {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(c.threads));
      ClothSpec spec;
      spec.particlesAlong1 = spec.particlesAlong2 = n;
      PbdSettings settings;
      settings.formulation = PbdFormulation::Pbd;
      settings.solver = c.solver;
      settings.relaxation = c.relaxation;
      settings.iterations = iterations;
      const std::unique_ptr<PbdSimulation> stretched = scenes::stretchedClothAfterOneStep(spec, settings);
      const PbdSimulation& sim = *stretched;
      const std::vector<double>& r = sim.convergence().residualHistory;
      const double perIteration = solveSeconds(sim) / iterations;
      for (std::size_t k = 0; k < r.size(); ++k)
      {
        csv << n << 'x' << n << ',' << c.name << ',' << c.threads << ',' << k + 1 << ',' << r[k] << ','
            << perIteration * double(k + 1) << '\n';
      }
      auto at = [&](std::size_t k) { return r[std::min(k, r.size()) - 1]; };
      std::printf("%-24s %3d %12.4g %12.4g %12.4g %14.4f\n", c.name.c_str(), c.threads, at(10), at(50),
        r.back(), 1e3 * perIteration);
      char row[256];
      std::snprintf(row, sizeof row, "| %d x %d | %s | %d | %.3g | %.3g | %.3g | %.3f |\n", n, n,
        c.name.c_str(), c.threads, at(10), at(50), r.back(), 1e3 * perIteration);
      table << row;
    }
  }
}

/// Least bytes one XPBD iteration streams with core's layout (doubles, int32 indices), each
/// array once per sweep (the floor pass and anything cached between constraints left out):
///   per link: ends 8, rest 8, broken 1, params 16, lambda read and written 16        49 B
///   per tet:  corners 16, rest volume 8, broken 1, params 16, lambda 16              57 B
///   per particle: position read and written 48, inverse mass 8 (once per batch)    112 B
double modelledBytesPerIteration(std::size_t particles, std::size_t links, std::size_t tets)
{
  return 49.0 * double(links) + 57.0 * double(tets) + 112.0 * double(particles);
}

const char* solverName(PbdSolver solver)
{
  return solver == PbdSolver::GaussSeidel ? "Gauss-Seidel"
    : solver == PbdSolver::Jacobi         ? "Jacobi"
                                          : "Parallel Gauss-Seidel";
}

void throughput(const bench::Options& options, int maxThreads)
{
  std::ofstream csv(options.csv + "_throughput.csv");
  csv << "mesh,tets,links,ordering,solver,threads,ms_per_iteration,ms_per_iteration_median,"
         "cpu_ms_per_iteration,time_over_bandwidth_bound,"
         "projections_per_second_per_thread,speedup,time_over_input_order,"
         "per_projection_time_over_box,state_hash\n";
  std::ofstream table(bench::tableBeside(options.csv + "_throughput.csv"));
  table << "| mesh | tets | links | solver | threads | ms / iteration | projections/s per thread | "
           "speed-up | x bw bound | per projection over the box |\n"
           "|---|---:|---:|---|---:|---:|---:|---:|---:|---:|\n";
  const std::vector<bench::NamedMesh> meshes =
    bench::benchmarkMeshes(options.smoke, options.dataDir, options.mesh);
  const bench::NamedMesh* box = bench::referenceBox(meshes);
  std::map<int, double> bandwidth; // threads -> triad bytes/s
  for (int threads : { 1, maxThreads })
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    bandwidth[threads] = bench::measureTriadBandwidth(options.smoke ? (1u << 20) : (1u << 24), options.smoke ? 2 : 5);
    std::printf("\ntriad bandwidth, %d thread(s): %.2f GB/s; cores this process gets (compute "
                "probe; bounds any speed-up): %.2f", threads, bandwidth[threads] / 1e9,
      bench::measureComputeParallelism(options.smoke ? 1 : 5));
  }
  std::printf("\n");
  // Seconds per projection of the reference box in its generated order, per solver and
  // thread count.
  std::map<std::pair<int, int>, double> boxPerProjection;
  std::printf("\nXPBD, 10 iterations per step, edges + tet volumes + floor. ms/iter: minimum (median) "
              "of %d run(s), wall time of the solve stages; 'cpu ms': least CPU time of the calling "
              "thread per iteration, whole step included (1 thread only; leaves out time other "
              "processes held the core); 'x bw': time over the modelled bytes per iteration at the "
              "triad bandwidth; '/input': time over the same mesh in input order; 'x box': "
              "per-projection time over %s's in input order\n",
    options.repeat, box ? box->name.c_str() : "(no box)");
  std::printf("%-22s %7s %7s %-6s %-22s %3s %8s %8s %8s %13s %7s %6s %6s %6s\n", "mesh", "tets",
    "links", "order", "solver", "thr", "ms/iter", "(median)", "cpu ms", "proj/s/thread", "speedup",
    "x bw", "/input", "x box");
  for (const auto& named : meshes)
  {
    std::map<std::pair<int, int>, double> inputOrder; // (solver, threads) -> s/iteration
    for (VertexOrdering ordering : { VertexOrdering::Input, VertexOrdering::Morton,
           VertexOrdering::ReverseCuthillMcKee })
    {
      for (PbdSolver solver : { PbdSolver::GaussSeidel, PbdSolver::Jacobi, PbdSolver::ParallelGaussSeidel })
      {
        double oneThread = 0.0;
        std::uint64_t firstHash = 0;
        for (int threads : { 1, maxThreads })
        {
          if (solver == PbdSolver::GaussSeidel && threads > 1)
          {
            continue; // sequential by definition
          }
          tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
          Body body;
          body.mesh.points = named.mesh.points;
          body.mesh.tets = named.mesh.tets;
          PbdSettings settings;
          settings.solver = solver;
          settings.floorEnabled = true;
          settings.volumes.compliance = 1e-10;
          std::unique_ptr<Simulation> wrapped;
          PbdSimulation* sim = nullptr;
          try
          {
            wrapped = makePbdSimulation(body, settings, ordering, &sim);
          }
          catch (const std::exception& error)
          {
            std::printf("%-22s skipped: %s\n", named.name.c_str(), error.what());
            break;
          }
          const double perIteration = double(sim->links().size() + sim->volumes().size());
          const int steps = options.smoke ? 2 : perIteration > 3e5 ? 5 : 20;
          sim->step(1.0 / 120.0); // warm-up
          std::vector<double> perIterationSeconds, cpuPerIteration;
          for (int r = 0; r < options.repeat; ++r)
          {
            const double before = solveSeconds(*sim);
            const double cpuBefore = bench::threadCpuSeconds();
            for (int s = 0; s < steps; ++s)
            {
              sim->step(1.0 / 120.0);
            }
            const double iterations = double(steps) * settings.iterations;
            cpuPerIteration.push_back((bench::threadCpuSeconds() - cpuBefore) / iterations);
            perIterationSeconds.push_back((solveSeconds(*sim) - before) / iterations);
          }
          const bench::MinMedian t = bench::minMedian(perIterationSeconds);
          const double cpu = threads == 1 ? bench::minMedian(cpuPerIteration).min : 0.0;
          const std::uint64_t hash = bench::hashPositions(wrapped->positions());
          if (threads == 1)
          {
            oneThread = t.min;
            firstHash = hash;
          }
          const auto key = std::make_pair(int(solver), threads);
          if (ordering == VertexOrdering::Input)
          {
            inputOrder[key] = t.min;
            if (box == &named)
            {
              boxPerProjection[key] = t.min / perIteration;
            }
          }
          const double overInput = inputOrder.count(key) ? t.min / inputOrder[key] : 0.0;
          const double overBox =
            boxPerProjection.count(key) ? t.min / perIteration / boxPerProjection[key] : 0.0;
          const double perThread = perIteration / t.min / threads;
          const double overBound = t.min /
            (modelledBytesPerIteration(named.mesh.points.size(), sim->links().size(), sim->volumes().size()) /
              bandwidth[threads]);
          std::printf("%-22s %7zu %7zu %-6s %-22s %3d %8.3f %8.3f %8.3f %13.3g %7.2f %6.2f %6.2f %6.2f %016llx%s\n",
            named.name.c_str(), sim->volumes().size(), sim->links().size(),
            vertexOrderingName(ordering), solverName(solver), threads, 1e3 * t.min, 1e3 * t.median,
            1e3 * cpu,
            perThread, oneThread / t.min, overBound, overInput, overBox, static_cast<unsigned long long>(hash),
            hash == firstHash ? "" : "  HASH DIFFERS");
          csv << named.name << ',' << sim->volumes().size() << ',' << sim->links().size() << ','
              << vertexOrderingName(ordering) << ',' << int(solver) << ',' << threads << ','
              << 1e3 * t.min << ',' << 1e3 * t.median << ',' << 1e3 * cpu << ',' << overBound << ',' << perThread << ',' << oneThread / t.min
              << ',' << overInput << ',' << overBox << ',' << hash << '\n';
          if (ordering == VertexOrdering::Morton)
          {
            // Boxes measured before the reference box have no ratio to it.
            char overBoxText[32] = "-";
            if (overBox > 0.0)
            {
              std::snprintf(overBoxText, sizeof overBoxText, "%.2f", overBox);
            }
            char row[320];
            std::snprintf(row, sizeof row, "| %s | %zu | %zu | %s | %d | %.3f | %.3g | %.2f | %.2f | %s |\n",
              named.name.c_str(), sim->volumes().size(), sim->links().size(), solverName(solver), threads,
              1e3 * t.min, perThread, oneThread / t.min, overBound, overBoxText);
            table << row;
          }
          if (hash != firstHash)
          {
            std::fprintf(stderr, "error: the state differs between thread counts\n");
            std::exit(1);
          }
        }
      }
    }
  }
}
} // namespace

int main(int argc, char** argv)
{
  const bench::Options options = bench::parseOptions(argc, argv, "bench_pbd", "bench_pbd");
  const int maxThreads = tbb::info::default_concurrency();
  if (options.mesh.empty())
  {
    convergence(options, maxThreads);
  }
  throughput(options, maxThreads);
  std::printf("\nCSV: %s_convergence.csv, %s_throughput.csv\n", options.csv.c_str(), options.csv.c_str());
  return 0;
}
