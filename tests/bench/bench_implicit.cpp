// Implicit against explicit integration: wall time per simulated second.
//
// For each mesh, a body dropped onto a floor just below it with the default material (rubber,
// E = 1e5 Pa, damping time 2 ms), at all threads:
//   - Euler-Cromer at its automatic (stable) step: ms per step, and ms per simulated second;
//   - Implicit Euler at 1/60 s, once with each CG preconditioner (block Jacobi; the coordinate
//     preconditioner, coordinate_preconditioner.h, with a complete or incomplete Cholesky factor
//     or, where the build has hypre, a BoomerAMG hierarchy): ms per step, Newton iterations per
//     step, CG iterations per Newton iteration, unconverged steps, and for the coordinate ones
//     their factorizations' time (set-up, not counted in ms per step) and the factor's memory
//     (for AMG: the hierarchy's operators and interpolations, as hypre stores them);
//   - Projective Dynamics at 1/60 s, once with each Cholesky backend (CHOLMOD supernodal,
//     Eigen simplicial): the factorization's time and memory, ms per step, iterations per
//     step, unconverged steps;
//   - Implicit Euler on steel (E = 200 GPa) with each CG preconditioner, over a quarter of the
//     frames.
// The last column is the implicit speed-up per simulated second over Euler-Cromer, measured in
// the same run. The explicit run is timed over a few steps only (its step cost does not change
// with time); the implicit runs over the first `frames` frames, which include the landing.
// Beside each implicit row, the bound of its linear solves at the memory bandwidth measured in
// the same run: block-Jacobi CG streams the assembled Hessian's 3x3 blocks and ~11 vectors per
// iteration; a Cholesky solve (Projective Dynamics per iteration, the coordinate preconditioner
// per CG iteration) streams its factor twice (forward and back) on one thread, and an AMG
// application about nine times (per coordinate: a smoothing sweep down, one up and the residual
// over every level). "x bound" is the measured solve time over that bound. Results also go to
// CSV and to a Markdown table beside it.
//
// Usage: bench_implicit [--smoke] [--data <shared data dir>] [--csv <file>] [--mesh <spec>]
#include "bench_meshes.h"
#include "bench_options.h"
#include "memory_bandwidth.h"

#include "softbody/massspring/amg_preconditioner.h"
#include "softbody/massspring/mass_spring_reordered.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <tbb/global_control.h>
#include <vector>

using namespace softbody;

namespace
{

constexpr double kFrame = 1.0 / 60.0;

double secondsSince(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

SceneSettings droppedOnTheFloor(const TetMesh& mesh, Integrator integrator)
{
  double lowest = 1e300;
  for (const Vec3& p : mesh.points)
  {
    lowest = std::min(lowest, p.z());
  }
  SceneSettings scene;
  scene.integrator = integrator;
  scene.floorEnabled = true;
  scene.floor.origin = Vec3(0, 0, lowest - 1e-3);
  if (isImplicit(integrator))
  {
    scene.timeStep = kFrame;
  }

  return scene;
}

struct Explicit
{
  double step = 0.0, secondsPerStep = 0.0;
};

Explicit timeExplicit(const TetMesh& mesh, bool smoke)
{
  Body body;
  body.mesh = mesh;
  // Renumbered for locality, as the filter builds it (mass_spring_reordered.h).
  const std::unique_ptr<Simulation> built =
    makeMassSpringSimulation(body, droppedOnTheFloor(mesh, Integrator::EulerCromer));
  Simulation& sim = *built;
  const double h = sim.stepSize();
  sim.advance(3 * h); // warm-up
  const int steps = smoke ? 3 : 20;
  const auto start = std::chrono::steady_clock::now();
  sim.advance(sim.time() + steps * h);
  return { h, secondsSince(start) / steps };
}

struct Implicit
{
  double secondsPerStep = 0.0;
  double iterationsPerStep = 0.0, linearPerIteration = 0.0;
  unsigned long long unconverged = 0, steps = 0;
  double factorSeconds = 0.0, factorMegabytes = 0.0;
  double forcesShare = 0.0, solveShare = 0.0; ///< of the wall time: element passes, linear solves
  std::uint64_t hash = 0;
  std::size_t warnings = 0;
  double factorBytes = 0.0;
  double cgPerStep = 0.0;
  double factorPassesPerStep = 0.0; ///< passes over the factor (or hierarchy) per step, on one thread
};

/// Passes over the factor per application: forward and back for a Cholesky solve; for one
/// V-cycle per coordinate, about three per coordinate (sweep down, sweep up, residual).
double factorPasses(LinearPreconditioner preconditioner)
{
  return preconditioner == LinearPreconditioner::AlgebraicMultigrid ? 9.0 : 2.0;
}

/// Bytes one block-Jacobi CG iteration streams: the Hessian's blocks (9 doubles and a column
/// index each; one per point and two per tet edge) and ~11 vector passes plus the inverted
/// diagonal per point.
double cgIterationBytes(const TetMesh& mesh)
{
  std::vector<std::uint64_t> edges;
  edges.reserve(6 * mesh.tets.size());
  for (const auto& tet : mesh.tets)
  {
    for (int a = 0; a < 4; ++a)
    {
      for (int b = a + 1; b < 4; ++b)
      {
        const std::uint64_t i = std::min(tet[a], tet[b]), j = std::max(tet[a], tet[b]);
        edges.push_back(i << 32 | j);
      }
    }
  }
  std::sort(edges.begin(), edges.end());
  const double uniqueEdges = double(std::unique(edges.begin(), edges.end()) - edges.begin());
  const double points = double(mesh.points.size());
  return (points + 2.0 * uniqueEdges) * (9 * 8 + 4) + points * (11 * 24 + 72);
}

/// An implicit integrator with the linear-solver settings of one row.
struct Variant
{
  Integrator integrator;
  const char* solver;
  LinearPreconditioner preconditioner = LinearPreconditioner::BlockJacobi;
  CholeskyBackend cholesky = CholeskyBackend::CholmodSupernodal;
  bool steel = false; ///< E = 200 GPa, nu = 0.3, 7850 kg/m^3 instead of the default rubber
};

const Variant kVariants[] = {
  { Integrator::ImplicitEuler, "block Jacobi CG" },
  { Integrator::ImplicitEuler, "coordinate CG", LinearPreconditioner::Coordinate },
  { Integrator::ImplicitEuler, "incomplete-Cholesky CG", LinearPreconditioner::IncompleteCoordinate },
  { Integrator::ImplicitEuler, "AMG CG", LinearPreconditioner::AlgebraicMultigrid },
  { Integrator::ProjectiveDynamics, "CHOLMOD" },
  { Integrator::ProjectiveDynamics, "Eigen simplicial", LinearPreconditioner::BlockJacobi,
    CholeskyBackend::EigenSimplicial },
  // Stiff materials are where block Jacobi's iteration count explodes.
  { Integrator::ImplicitEuler, "steel, block Jacobi CG", LinearPreconditioner::BlockJacobi,
    CholeskyBackend::CholmodSupernodal, true },
  { Integrator::ImplicitEuler, "steel, coordinate CG", LinearPreconditioner::Coordinate,
    CholeskyBackend::CholmodSupernodal, true },
  { Integrator::ImplicitEuler, "steel, incomplete-Cholesky CG", LinearPreconditioner::IncompleteCoordinate,
    CholeskyBackend::CholmodSupernodal, true },
  { Integrator::ImplicitEuler, "steel, AMG CG", LinearPreconditioner::AlgebraicMultigrid,
    CholeskyBackend::CholmodSupernodal, true },
};

Implicit timeImplicit(const TetMesh& mesh, const Variant& variant, int frames)
{
  Body body;
  body.mesh = mesh;
  if (variant.steel)
  {
    body.material.physical.youngsModulus = 2e11;
    body.material.physical.poissonRatio = 0.3;
    body.material.physical.density = 7850.0;
    frames = std::max(1, frames / 4); // block Jacobi takes ~10x longer per step here
  }
  SceneSettings scene = droppedOnTheFloor(mesh, variant.integrator);
  scene.implicit.preconditioner = variant.preconditioner;
  scene.implicit.cholesky = variant.cholesky;
  const std::unique_ptr<Simulation> built = makeMassSpringSimulation(body, scene);
  Simulation& sim = *built;
  const Simulation* inner = &sim;
  if (const auto* reordered = dynamic_cast<const ReorderedSimulation*>(inner))
  {
    inner = &reordered->inner();
  }
  const auto& massSpring = dynamic_cast<const MassSpringSimulation&>(*inner);
  Implicit r;
  const auto start = std::chrono::steady_clock::now();
  for (int f = 1; f <= frames; ++f)
  {
    sim.advance(f * kFrame);
  }
  const double seconds = secondsSince(start);
  const ImplicitConvergence& c = *massSpring.implicitConvergence();
  r.steps = c.steps;
  r.unconverged = c.unconvergedSteps;
  r.iterationsPerStep = double(c.iterationsTotal) / double(c.steps);
  r.linearPerIteration = c.iterationsTotal ? double(c.linearIterationsTotal) / double(c.iterationsTotal) : 0.0;
  if (const ProjectiveDynamicsStepper* pd = massSpring.projectiveDynamics())
  {
    r.factorSeconds = pd->factorSeconds();
    r.factorMegabytes = double(pd->factorBytes()) / 1e6;
    r.factorBytes = double(pd->factorBytes());
    r.factorPassesPerStep = 2.0 * r.iterationsPerStep;
  }
  if (const CoordinatePreconditioner* coordinate = massSpring.coordinatePreconditioner())
  {
    r.factorSeconds = coordinate->factorSeconds();
    r.factorMegabytes = double(coordinate->factorBytes()) / 1e6;
    r.factorBytes = double(coordinate->factorBytes());
  }
  r.cgPerStep = double(c.linearIterationsTotal) / double(c.steps);
  if (massSpring.coordinatePreconditioner())
  {
    // One application per CG iteration (and one before).
    r.factorPassesPerStep = factorPasses(variant.preconditioner) * r.cgPerStep;
  }
  r.warnings = sim.warnings().size();
  // Factorizations are set-up, not steps: reported on their own.
  r.secondsPerStep = (seconds - r.factorSeconds) / double(c.steps);
  r.hash = bench::hashPositions(sim.positions());
  for (const StageTiming& t : sim.stageTimings())
  {
    if (t.stage == Stage::Forces)
    {
      r.forcesShare = t.seconds / seconds;
    }
    if (t.stage == Stage::LinearSolve)
    {
      r.solveShare = t.seconds / seconds;
    }
  }
  return r;
}

/// Tip height of a cantilever (20 x 2 x 2 cells of 1 cm, pinned at x = 0, default material)
/// released from rest under gravity, sampled every 1/60 s over one second: it swings about its
/// static sag, so the samples measure both the oscillation (phase, amplitude: what numerical
/// damping removes) and the sag.
std::vector<double> cantileverTip(Integrator integrator, double step, double& seconds)
{
  Body body;
  body.mesh = makeTetBox(20, 2, 2, 0.01, Vec3(0, 0, 1));
  body.pinned.assign(body.mesh.points.size(), 0);
  std::vector<std::size_t> tip;
  for (std::size_t i = 0; i < body.mesh.points.size(); ++i)
  {
    body.pinned[i] = body.mesh.points[i].x() < 1e-9 ? 1 : 0;
    if (body.mesh.points[i].x() > 0.2 - 1e-9)
    {
      tip.push_back(i);
    }
  }
  SceneSettings scene;
  scene.integrator = integrator;
  scene.timeStep = step;
  scene.implicit.tolerance = 1e-5;
  scene.implicit.maxIterations = 500;
  MassSpringSimulation sim(body, scene);
  std::vector<double> heights;
  const auto start = std::chrono::steady_clock::now();
  for (int frame = 1; frame <= 60; ++frame)
  {
    sim.advance(frame * kFrame);
    double z = 0.0;
    for (std::size_t i : tip)
    {
      z += sim.positions()[i].z() / double(tip.size());
    }
    heights.push_back(z);
  }
  seconds = secondsSince(start);
  return heights;
}

double rmsDifference(const std::vector<double>& a, const std::vector<double>& b)
{
  double sum = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k)
  {
    sum += (a[k] - b[k]) * (a[k] - b[k]);
  }
  return std::sqrt(sum / double(a.size()));
}

/// Error against wall time on the cantilever: the reference is Euler-Cromer at a quarter of its
/// automatic step, checked against half of it (their difference is printed: the reference's
/// own error). Error = RMS over the 60 frames of the tip height difference, relative to the
/// reference's RMS tip deflection.
void accuracyTable(std::ofstream& csv)
{
  double seconds = 0.0;
  Body probe;
  probe.mesh = makeTetBox(20, 2, 2, 0.01, Vec3(0, 0, 1));
  const double automatic = MassSpringSimulation(probe, SceneSettings{}).stepSize();
  const std::vector<double> reference = cantileverTip(Integrator::EulerCromer, automatic / 4, seconds);
  const std::vector<double> half = cantileverTip(Integrator::EulerCromer, automatic / 2, seconds);
  double deflection = 0.0;
  for (double z : reference)
  {
    deflection += (z - 1.02) * (z - 1.02) / double(reference.size());
  }
  deflection = std::sqrt(deflection);
  std::printf("\nCantilever (1 s, tip height each frame): reference Euler-Cromer at %.3g s; at %.3g s "
              "it differs by %.2g of the deflection\n", automatic / 4, automatic / 2,
    rmsDifference(half, reference) / deflection);
  std::printf("%-20s %10s %10s %12s\n", "integrator", "step [s]", "wall [s]", "rel. error");
  csv << "\nscene,integrator,step_s,wall_s,relative_error\n";
  const auto row = [&](Integrator integrator, double step) {
    const std::vector<double> tip = cantileverTip(integrator, step, seconds);
    const double error = rmsDifference(tip, reference) / deflection;
    std::printf("%-20s %10.3g %10.3f %12.3g\n", integratorName(integrator), step, seconds, error);
    csv << "cantilever," << integratorName(integrator) << ',' << step << ',' << seconds << ',' << error << '\n';
  };
  row(Integrator::EulerCromer, automatic);
  for (Integrator integrator : { Integrator::ImplicitEuler, Integrator::ProjectiveDynamics })
  {
    for (double step : { kFrame, kFrame / 4, kFrame / 16, kFrame / 64 })
    {
      row(integrator, step);
    }
  }
}

} // namespace

int main(int argc, char** argv)
{
  const bench::Options options =
    bench::parseOptions(argc, argv, "bench_implicit", "bench_implicit.csv");
  const int frames = options.smoke ? 2 : 12;
  const std::vector<bench::NamedMesh> meshes = bench::benchmarkMeshes(options.smoke, options.dataDir, options.mesh);
  const std::size_t probe = options.smoke ? (1u << 22) : (1u << 25);
  const double bandwidth = bench::measureTriadBandwidth(probe, 5);
  double serialBandwidth = 0.0;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    serialBandwidth = bench::measureTriadBandwidth(probe, 5);
  }
  std::printf("triad bandwidth %.1f GB/s at all threads, %.1f GB/s on one thread\n", bandwidth * 1e-9,
    serialBandwidth * 1e-9);

  std::ofstream csv(options.csv);
  // The same rows as a table for docs/performance.md (scripts/update_docs_tables.py).
  std::ofstream table(bench::tableBeside(options.csv));
  table << "| mesh | tets | integrator (linear solver) | ms/step | s per simulated s | iterations/step | "
           "CG/Newton | unconverged | factor s | factor MB | forces / solve | solve ms/step | x bound | speed-up |\n"
           "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|\n";
  char line[512];
  csv << "mesh,vertices,tets,integrator,step_s,ms_per_step,s_per_simulated_s,iterations_per_step,"
         "cg_per_newton,unconverged_steps,steps,factor_s,factor_MB,speedup_over_explicit,solver\n";
  std::printf("%d frames of 1/60 s, dropped onto a floor; explicit = Euler-Cromer at its stable step\n\n", frames);
  std::printf("%-22s %7s %-37s %9s %9s %10s %6s %6s %5s %8s %8s %8s %11s\n", "mesh", "tets", "integrator",
    "step [s]", "ms/step", "s / sim s", "it/st", "cg/it", "unconv", "factor s", "factor MB", "speedup",
    "forces/solve");
  for (const auto& named : meshes)
  {
    Explicit ec;
    try
    {
      ec = timeExplicit(named.mesh, options.smoke);
    }
    catch (const std::exception& error)
    {
      std::printf("%-22s skipped: %s\n", named.name.c_str(), error.what());
      continue;
    }
    const double explicitPerSecond = ec.secondsPerStep / ec.step;
    std::printf("%-22s %7zu %-37s %9.2e %9.3f %10.1f\n", named.name.c_str(), named.mesh.tets.size(),
      "Euler-Cromer", ec.step, 1e3 * ec.secondsPerStep, explicitPerSecond);
    csv << named.name << ',' << named.mesh.points.size() << ',' << named.mesh.tets.size()
        << ",Euler-Cromer," << ec.step << ',' << 1e3 * ec.secondsPerStep << ',' << explicitPerSecond
        << ",,,,,,,1,\n";
    std::snprintf(line, sizeof line, "| %s | %zu | Euler-Cromer (stable step %.2e s) | %.2f | %.0f | | | | | | | | | 1 |\n",
      named.name.c_str(), named.mesh.tets.size(), ec.step, 1e3 * ec.secondsPerStep, explicitPerSecond);
    table << line;
    for (const Variant& variant : kVariants)
    {
      if (variant.preconditioner == LinearPreconditioner::AlgebraicMultigrid && !algebraicMultigridAvailable())
      {
        continue; // a build without hypre
      }
      const Implicit r = timeImplicit(named.mesh, variant, frames);
      const double perSecond = r.secondsPerStep / kFrame;
      // The explicit run is rubber's: no speed-up is claimed for steel against it.
      const double speedup = variant.steel ? std::nan("") : explicitPerSecond / perSecond;
      const std::string label = std::string(integratorName(variant.integrator)) + " (" + variant.solver + ")";
      std::printf("%-22s %7s %-37s %9.2e %9.1f %10.2f %6.1f %6.1f %5llu %8.3f %8.1f %8.0f %5.0f%%/%3.0f%%%s\n", "", "",
        label.c_str(), kFrame, 1e3 * r.secondsPerStep, perSecond, r.iterationsPerStep,
        r.linearPerIteration, r.unconverged, r.factorSeconds, r.factorMegabytes,
        speedup, 100 * r.forcesShare, 100 * r.solveShare,
        r.warnings ? "  (warned: fell back)" : "");
      csv << named.name << ',' << named.mesh.points.size() << ',' << named.mesh.tets.size() << ','
          << integratorName(variant.integrator) << ',' << kFrame << ',' << 1e3 * r.secondsPerStep << ','
          << perSecond << ',' << r.iterationsPerStep << ',' << r.linearPerIteration << ','
          << r.unconverged << ',' << r.steps << ',' << r.factorSeconds << ',' << r.factorMegabytes
          << ',' << (variant.steel ? std::string() : std::to_string(speedup)) << ',' << variant.solver << '\n';
      const double solveSeconds = r.secondsPerStep * r.solveShare;
      const double bound = r.cgPerStep * cgIterationBytes(named.mesh) / bandwidth +
        r.factorPassesPerStep * r.factorBytes / serialBandwidth;
      std::printf("%-22s %7s %-37s solve %.0f ms/step, bound %.0f ms/step: %.1fx the bound\n", "", "", "",
        1e3 * solveSeconds, 1e3 * bound, solveSeconds / bound);
      std::snprintf(line, sizeof line, "| | | %s | %.0f | %.1f | %.1f | %.1f | %llu | %.2f | %.1f | %.0f %% / %.0f %% | %.0f | %.1f | %s |\n",
        label.c_str(), 1e3 * r.secondsPerStep, perSecond, r.iterationsPerStep, r.linearPerIteration,
        r.unconverged, r.factorSeconds, r.factorMegabytes, 100 * r.forcesShare, 100 * r.solveShare,
        1e3 * solveSeconds, solveSeconds / bound,
        variant.steel ? "" : std::to_string(static_cast<int>(std::lround(speedup))).c_str());
      table << line;
    }
  }
  std::snprintf(line, sizeof line, "\nBounds at the triad bandwidth measured in the same run: %.1f GB/s at "
    "all threads (CG), %.1f GB/s on one thread (Cholesky solves).\n", bandwidth * 1e-9, serialBandwidth * 1e-9);
  table << line;
  if (!options.smoke)
  {
    accuracyTable(csv);
  }
  std::printf("\nCSV written to %s\n", options.csv.c_str());
  return 0;
}
