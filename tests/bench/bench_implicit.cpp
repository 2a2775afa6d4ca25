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
#include "softbody/mesh/mesh_generators.h"

#include <chrono>
#include <cmath>
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
  double forcesShare = 0.0, solveShare = 0.0; ///< of the wall time: element passes, linear solves
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
  BodyDescription body;
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
  BodyDescription probe;
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

  std::ofstream csv(options.csv);
  csv << "mesh,vertices,tets,integrator,step_s,ms_per_step,s_per_simulated_s,iterations_per_step,"
         "cg_per_newton,unconverged_steps,steps,factor_s,factor_MB,speedup_over_explicit\n";
  std::printf("%d frames of 1/60 s, dropped onto a floor; explicit = Euler-Cromer at its stable step\n\n", frames);
  std::printf("%-22s %7s %-20s %9s %9s %10s %6s %6s %5s %8s %8s %8s %11s\n", "mesh", "tets", "integrator",
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
    std::printf("%-22s %7zu %-20s %9.2e %9.3f %10.1f\n", named.name.c_str(), named.mesh.tets.size(),
      "Euler-Cromer", ec.step, 1e3 * ec.secondsPerStep, explicitPerSecond);
    csv << named.name << ',' << named.mesh.points.size() << ',' << named.mesh.tets.size()
        << ",Euler-Cromer," << ec.step << ',' << 1e3 * ec.secondsPerStep << ',' << explicitPerSecond
        << ",,,,,,,1\n";
    for (Integrator integrator : { Integrator::ImplicitEuler, Integrator::ProjectiveDynamics })
    {
      const Implicit r = timeImplicit(named.mesh, integrator, frames);
      const double perSecond = r.secondsPerStep / kFrame;
      std::printf("%-22s %7s %-20s %9.2e %9.1f %10.2f %6.1f %6.1f %5llu %8.3f %8.1f %8.0f %5.0f%%/%3.0f%%\n", "", "",
        integratorName(integrator), kFrame, 1e3 * r.secondsPerStep, perSecond, r.iterationsPerStep,
        r.linearPerIteration, r.unconverged, r.factorSeconds, r.factorMegabytes,
        explicitPerSecond / perSecond, 100 * r.forcesShare, 100 * r.solveShare);
      csv << named.name << ',' << named.mesh.points.size() << ',' << named.mesh.tets.size() << ','
          << integratorName(integrator) << ',' << kFrame << ',' << 1e3 * r.secondsPerStep << ','
          << perSecond << ',' << r.iterationsPerStep << ',' << r.linearPerIteration << ','
          << r.unconverged << ',' << r.steps << ',' << r.factorSeconds << ',' << r.factorMegabytes
          << ',' << explicitPerSecond / perSecond << '\n';
    }
  }
  if (!options.smoke)
  {
    accuracyTable(csv);
  }
  std::printf("\nCSV written to %s\n", options.csv.c_str());
  return 0;
}
