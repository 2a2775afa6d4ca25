// PBD/XPBD solvers: convergence against iterations and against time, and projection throughput.
//
// 1. The PBD thesis's Figures 5.3 and 5.4: a 50 x 50 and a 100 x 100 cloth stretched 16 times
//    and released (no gravity, PBD stiffness 1), one step of N iterations, the residual after
//    each iteration, for Gauss-Seidel, SOR at several factors, averaged Jacobi and parallel
//    (colored) Gauss-Seidel at 1 and all threads. Time per iteration is the solver's own stage
//    time (the residual evaluation is timed apart), so "residual against time" is what a user
//    pays. Written as CSV; tests/bench/plot_pbd_convergence.py draws the PNG.
// 2. XPBD throughput on the benchmark tet meshes: constraint projections (edges + tets) per
//    second per thread, with the speed-up of the colored solver from 1 to all threads, and a
//    state hash showing both thread counts computed the same thing.
//
// Usage: bench_pbd [--smoke] [--data <shared data dir>] [--csv <prefix>]
#include "bench_meshes.h"
#include "scenes/stretched_cloth.h"
#include "bench_options.h"

#include "softbody/pbd/cloth.h"
#include "softbody/pbd/pbd_simulation.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>

using namespace softbody;

namespace
{
/// Time spent projecting constraints (every solve stage of the plan), residual excluded.
double solveSeconds(const PbdSimulation& sim)
{
  const StepPlan& plan = sim.stepPlan();
  double seconds = 0.0;
  for (Stage stage : { Stage::SolveLinks, Stage::SolveVolumes, Stage::SolveAttachments, Stage::SolveFloor })
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
  std::vector<SolverCase> cases = { { "Gauss-Seidel", PbdSolver::GaussSeidel, 1.0, 1 },
    { "SOR 1.2", PbdSolver::GaussSeidel, 1.2, 1 }, { "SOR 1.5", PbdSolver::GaussSeidel, 1.5, 1 },
    { "SOR 1.8", PbdSolver::GaussSeidel, 1.8, 1 }, { "Jacobi", PbdSolver::Jacobi, 1.0, 1 },
    { "Jacobi", PbdSolver::Jacobi, 1.0, maxThreads },
    { "Parallel Gauss-Seidel", PbdSolver::ParallelGaussSeidel, 1.0, 1 },
    { "Parallel Gauss-Seidel", PbdSolver::ParallelGaussSeidel, 1.0, maxThreads } };
  const std::vector<int> sizes = options.smoke ? std::vector<int>{ 20 } : std::vector<int>{ 50, 100 };
  const int iterations = options.smoke ? 10 : 200;
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
    }
  }
}

void throughput(const bench::Options& options, int maxThreads)
{
  std::ofstream csv(options.csv + "_throughput.csv");
  csv << "mesh,tets,links,solver,threads,ms_per_iteration,projections_per_second_per_thread,speedup,state_hash\n";
  const std::vector<bench::NamedMesh> meshes = bench::benchmarkMeshes(options.smoke, options.dataDir);
  std::printf("\nXPBD, 10 iterations per step, edges + tet volumes + floor\n");
  std::printf("%-22s %8s %8s %-22s %3s %12s %16s %8s\n", "mesh", "tets", "links", "solver", "thr",
    "ms/iter", "proj/s/thread", "speedup");
  for (const auto& named : meshes)
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
        PbdBody body;
        body.points = named.mesh.points;
        body.tets = named.mesh.tets;
        PbdSettings settings;
        settings.solver = solver;
        settings.floorEnabled = true;
        settings.volumes.compliance = 1e-10;
        std::unique_ptr<PbdSimulation> sim;
        try
        {
          sim = std::make_unique<PbdSimulation>(body, settings);
        }
        catch (const std::exception& error)
        {
          std::printf("%-22s skipped: %s\n", named.name.c_str(), error.what());
          break;
        }
        const int steps = options.smoke ? 2 : 20;
        for (int s = 0; s < steps; ++s)
        {
          sim->step(1.0 / 120.0);
        }
        const double seconds = solveSeconds(*sim);
        const double iterations = double(steps) * settings.iterations;
        const double projections = double(sim->links().size() + sim->volumes().size()) * iterations;
        const std::uint64_t hash = bench::hashPositions(sim->positions());
        if (threads == 1)
        {
          oneThread = seconds;
          firstHash = hash;
        }
        const double perThread = projections / seconds / threads;
        std::printf("%-22s %8zu %8zu %-22s %3d %12.3f %16.3g %8.2f%s\n", named.name.c_str(),
          sim->volumes().size(), sim->links().size(),
          solver == PbdSolver::GaussSeidel ? "Gauss-Seidel" : solver == PbdSolver::Jacobi ? "Jacobi" : "Parallel Gauss-Seidel",
          threads, 1e3 * seconds / iterations, perThread, oneThread / seconds,
          hash == firstHash ? "" : "  HASH DIFFERS");
        csv << named.name << ',' << sim->volumes().size() << ',' << sim->links().size() << ','
            << int(solver) << ',' << threads << ',' << 1e3 * seconds / iterations << ',' << perThread << ','
            << oneThread / seconds << ',' << hash << '\n';
        if (hash != firstHash)
        {
          std::fprintf(stderr, "error: the state differs between thread counts\n");
          std::exit(1);
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
  convergence(options, maxThreads);
  throughput(options, maxThreads);
  std::printf("\nCSV: %s_convergence.csv, %s_throughput.csv\n", options.csv.c_str(), options.csv.c_str());
  return 0;
}
