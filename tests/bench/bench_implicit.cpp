// Implicit against explicit integration: wall time per simulated second.
//
// For each mesh, a body dropped onto a floor just below it with the default material (rubber,
// E = 1e5 Pa, damping time 2 ms), at all threads:
//   - Euler-Cromer at its automatic (stable) step: ms per step, and ms per simulated second;
//   - Implicit Euler at 1/60 s: ms per step, Newton iterations per step, CG iterations per
//     Newton iteration, unconverged steps;
//   - Projective Dynamics at 1/60 s: the Cholesky factorization's time and memory (nonzeros of
//     the factor; 12 bytes each with its row index), ms per step, iterations per step,
//     unconverged steps.
// The last column is the implicit speed-up per simulated second over Euler-Cromer, measured in
// the same run. The explicit run is timed over a few steps only (its step cost does not change
// with time); the implicit runs over the first `frames` frames, which include the landing.
// Results also go to CSV.
//
// Usage: bench_implicit [--smoke] [--data <shared data dir>] [--csv <file>] [--mesh <spec>]
#include "bench_meshes.h"
#include "bench_options.h"

#include "softbody/massspring/mass_spring_reordered.h"
#include "softbody/massspring/mass_spring_simulation.h"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>

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
  if (getenv("MAXIT")) scene.implicit.maxIterations = atoi(getenv("MAXIT"));
  if (getenv("HIST")) scene.implicit.projectiveHistory = atoi(getenv("HIST"));
  return scene;
}

struct Explicit
{
  double step = 0.0, secondsPerStep = 0.0;
};

Explicit timeExplicit(const TetMesh& mesh, bool smoke)
{
  BodyDescription body;
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
  std::uint64_t hash = 0;
};

Implicit timeImplicit(const TetMesh& mesh, Integrator integrator, int frames)
{
  BodyDescription body;
  body.mesh = mesh;
  const std::unique_ptr<Simulation> built =
    makeMassSpringSimulation(body, droppedOnTheFloor(mesh, integrator));
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
    if (getenv("TRACE"))
    {
      std::printf("frame %d:", f);
      for (double r : massSpring.implicitConvergence()->residualHistory) std::printf(" %.2g", r);
      std::printf(" halvings %llu\n", massSpring.implicitConvergence()->lineSearchHalvings);
    }
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
    r.factorMegabytes = 12.0 * double(pd->factorNonZeros()) / 1e6;
  }
  // The one factorization is set-up, not a step: reported on its own.
  r.secondsPerStep = (seconds - r.factorSeconds) / double(c.steps);
  r.hash = bench::hashPositions(sim.positions());
  if (getenv("TRACE"))
  {
    for (const StageTiming& t : sim.stageTimings()) std::printf("  %s: %.3f s\n", t.label.c_str(), t.seconds);
  }
  return r;
}

} // namespace

int main(int argc, char** argv)
{
  const bench::Options options =
    bench::parseOptions(argc, argv, "bench_implicit", "bench_implicit.csv");
  const int frames = options.smoke ? 2 : 12;
  const std::vector<bench::NamedMesh> meshes = bench::benchmarkMeshes(options.smoke, options.dataDir, options.mesh);

  std::ofstream csv(options.csv);
  csv << "mesh,vertices,tets,integrator,step_s,ms_per_step,s_per_simulated_s,iterations_per_step,"
         "cg_per_newton,unconverged_steps,steps,factor_s,factor_MB,speedup_over_explicit\n";
  std::printf("%d frames of 1/60 s, dropped onto a floor; explicit = Euler-Cromer at its stable step\n\n", frames);
  std::printf("%-22s %7s %-20s %9s %9s %10s %6s %6s %5s %8s %8s %8s\n", "mesh", "tets", "integrator",
    "step [s]", "ms/step", "s / sim s", "it/st", "cg/it", "unconv", "factor s", "factor MB", "speedup");
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
    std::printf("%-22s %7zu %-20s %9.2e %9.3f %10.1f\n", named.name.c_str(), named.mesh.tets.size(),
      "Euler-Cromer", ec.step, 1e3 * ec.secondsPerStep, explicitPerSecond);
    csv << named.name << ',' << named.mesh.points.size() << ',' << named.mesh.tets.size()
        << ",Euler-Cromer," << ec.step << ',' << 1e3 * ec.secondsPerStep << ',' << explicitPerSecond
        << ",,,,,,,1\n";
    for (Integrator integrator : { Integrator::ImplicitEuler, Integrator::ProjectiveDynamics })
    {
      if (getenv("SKIP_PD") && integrator == Integrator::ProjectiveDynamics) continue;
      const Implicit r = timeImplicit(named.mesh, integrator, frames);
      const double perSecond = r.secondsPerStep / kFrame;
      std::printf("%-22s %7s %-20s %9.2e %9.1f %10.2f %6.1f %6.1f %5llu %8.3f %8.1f %8.0f\n", "", "",
        integratorName(integrator), kFrame, 1e3 * r.secondsPerStep, perSecond, r.iterationsPerStep,
        r.linearPerIteration, r.unconverged, r.factorSeconds, r.factorMegabytes,
        explicitPerSecond / perSecond);
      csv << named.name << ',' << named.mesh.points.size() << ',' << named.mesh.tets.size() << ','
          << integratorName(integrator) << ',' << kFrame << ',' << 1e3 * r.secondsPerStep << ','
          << perSecond << ',' << r.iterationsPerStep << ',' << r.linearPerIteration << ','
          << r.unconverged << ',' << r.steps << ',' << r.factorSeconds << ',' << r.factorMegabytes
          << ',' << explicitPerSecond / perSecond << '\n';
    }
  }
  std::printf("\nCSV written to %s\n", options.csv.c_str());
  return 0;
}
