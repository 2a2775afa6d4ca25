// Error-controlled steps against the best fixed step in hindsight: for each scene, integrator,
// tolerance and judge (the integrator's embedded estimate, or step doubling), the error the
// controller achieves (against a BDF2 reference at a tiny fixed step), its wall time, and the
// wall time of the largest fixed step that meets the same error, measured in the same run. The
// tolerance is an error per simulated second, so over a scene of T seconds both are held to
// tolerance x T. The cost ratio is the controller's price for not knowing the step beforehand
// (the target: within ~2x).
// Writes a CSV and, beside it, the table docs/accuracy.md shows (scripts/bench.sh).
#include "bench_options.h"

#include "softbody/common/errors.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <vector>

using namespace softbody;

namespace
{

struct BenchScene
{
  std::string name;
  Body body;
  double endTime, frame;
};

/// A bar of 2 x 2 x 10 cells hanging from its pinned top face, released from rest, undamped.
BenchScene hangingBar()
{
  BenchScene s{ "hanging bar (network)", {}, 0.3, 0.05 };
  s.body.mesh = makeTetBox(2, 2, 10, 0.02, Vec3(0, 0, 1));
  s.body.material.physical.dampingTime = 0.0;
  s.body.pinned.assign(s.body.mesh.points.size(), 0);
  for (std::size_t i = 0; i < s.body.mesh.points.size(); ++i)
  {
    s.body.pinned[i] = s.body.mesh.points[i].z() > 1.2 - 1e-9 ? 1 : 0;
  }
  return s;
}

/// A corotated cantilever of 10 x 2 x 2 cells pinned at x = 0, released under gravity, with
/// the default damping.
BenchScene cantilever()
{
  BenchScene s{ "cantilever (corotated)", {}, 0.3, 0.05 };
  s.body.mesh = makeTetBox(10, 2, 2, 0.02, Vec3(0, 0, 1));
  s.body.material.model = MaterialModel::Corotated;
  s.body.pinned.assign(s.body.mesh.points.size(), 0);
  for (std::size_t i = 0; i < s.body.mesh.points.size(); ++i)
  {
    s.body.pinned[i] = s.body.mesh.points[i].x() < 1e-9 ? 1 : 0;
  }
  return s;
}

struct Run
{
  bool ok = false;
  double error = 0.0; ///< the largest distance to the reference over the frames [m]
  double ms = 0.0;
  unsigned long long steps = 0, rejected = 0;
};

/// Runs the scene frame by frame; the positions at each frame go to `frames` (or are compared
/// with `reference`).
Run run(const BenchScene& scene, const SceneSettings& settings, const std::vector<std::vector<Vec3>>* reference,
  std::vector<std::vector<Vec3>>* frames = nullptr)
{
  Run r;
  try
  {
    const auto start = std::chrono::steady_clock::now();
    MassSpringSimulation sim(scene.body, settings);
    const int count = static_cast<int>(std::lround(scene.endTime / scene.frame));
    for (int f = 1; f <= count; ++f)
    {
      sim.advance(scene.frame * f);
      if (const StepControlReport* controller = sim.stepControlReport()) // null with fixed steps
      {
        r.rejected += controller->rejectedSteps;
      }
      if (frames)
      {
        frames->push_back(sim.positions());
      }
      if (reference)
      {
        const std::vector<Vec3>& x = sim.positions();
        for (std::size_t i = 0; i < x.size(); ++i)
        {
          const double d = (x[i] - (*reference)[static_cast<std::size_t>(f - 1)][i]).norm();
          r.error = std::isfinite(d) ? std::max(r.error, d) : std::numeric_limits<double>::infinity();
        }
      }
    }
    r.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    r.steps = sim.stepCount();
    r.ok = std::isfinite(r.error);
  }
  catch (const std::exception&)
  {
    r.ok = false; // a blow-up or a refused step: not a step that meets anything
  }
  return r;
}

SceneSettings settingsFor(Integrator integrator)
{
  SceneSettings s;
  s.integrator = integrator;
  s.implicit.tolerance = 1e-9;
  s.implicit.maxIterations = 100;
  return s;
}

} // namespace

int main(int argc, char** argv)
{
  const bench::Options options = bench::parseOptions(argc, argv, "bench_error_control", "error_control.csv");
  std::ofstream csv(options.csv);
  csv << "scene,integrator,judge,tolerance,allowed_error,achieved_error,steps,rejected,ms,best_fixed_step,fixed_error,"
         "fixed_ms,cost_ratio\n";
  const std::string md = bench::tableBeside(options.csv);
  std::ofstream table(md);
  table << "| scene | integrator | judge | tolerance [m/s] | allowed over the run [m] | achieved error [m] | x allowed | "
           "steps (rejected) | ms | best fixed step [s] | its ms | cost x best fixed |\n"
           "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::printf("%-24s %-16s %-13s %9s %9s %11s %7s %9s %9s %11s %11s %9s %7s\n", "scene", "integrator", "judge",
    "tolerance", "allowed", "achieved", "x allw", "steps", "rejected", "ms", "best fixed", "fixed ms", "ratio");
  int status = 0;
  std::vector<BenchScene> scenes{ hangingBar() };
  if (!options.smoke)
  {
    scenes.push_back(cantilever());
  }
  for (const BenchScene& scene : scenes)
  {
    SceneSettings referenceSettings = settingsFor(Integrator::Bdf2);
    referenceSettings.timeStep = options.smoke ? 1e-4 : 1e-5;
    std::vector<std::vector<Vec3>> reference;
    run(scene, referenceSettings, nullptr, &reference);
    struct Case
    {
      Integrator integrator;
      double tolerance;
      bool stepDoubling = false; ///< instead of the integrator's embedded estimate, where it has one
    };
    std::vector<Case> cases{ { Integrator::Bdf2, 1e-3 }, { Integrator::Bdf2, 1e-3, true } };
    if (!options.smoke)
    {
      // Step doubling beside the embedded estimate at the tolerances it takes seconds at.
      cases = { { Integrator::Bdf2, 1e-3 }, { Integrator::Bdf2, 1e-3, true }, { Integrator::Bdf2, 1e-4 },
        { Integrator::Bdf2, 1e-4, true }, { Integrator::Bdf2, 1e-5 }, { Integrator::ImplicitEuler, 1e-3 },
        { Integrator::ImplicitEuler, 1e-3, true }, { Integrator::ImplicitEuler, 1e-4 }, { Integrator::Verlet, 1e-3 },
        { Integrator::Verlet, 1e-3, true }, { Integrator::Verlet, 1e-5 }, { Integrator::Verlet, 1e-5, true },
        { Integrator::EulerCromer, 1e-3 }, { Integrator::EulerCromer, 1e-4 } };
    }
    for (const Case& c : cases)
    {
      SceneSettings adaptive = settingsFor(c.integrator);
      adaptive.stepControl = StepControl::ErrorControlled;
      adaptive.errorTolerance = c.tolerance;
      adaptive.stepDoubling = c.stepDoubling;
      const char* judge = factsOf(c.integrator).localError && !c.stepDoubling ? "embedded" : "step doubling";
      const Run controlled = run(scene, adaptive, &reference);
      // What the tolerance allows over the scene: it is an error per simulated second.
      const double allowed = c.tolerance * scene.endTime;
      const auto fixedRun = [&](double step) {
        SceneSettings s = settingsFor(c.integrator);
        s.timeStep = step;
        return run(scene, s, &reference);
      };
      const auto meets = [&](const Run& r) { return r.ok && r.error <= allowed; };
      // The best fixed step in hindsight: the frame interval halved until the error meets the
      // allowance (a blown-up explicit run does not), then bisected between that step and the
      // failing one before it, to 2^(1/8) (9 %).
      double step = scene.frame;
      Run fixed = fixedRun(step);
      for (int halving = 0; halving < 16 && !meets(fixed); ++halving)
      {
        step *= 0.5;
        fixed = fixedRun(step);
      }
      if (meets(fixed) && step < scene.frame)
      {
        double failing = 2.0 * step;
        for (int bisection = 0; bisection < 3; ++bisection)
        {
          const double middle = std::sqrt(step * failing);
          const Run tried = fixedRun(middle);
          if (meets(tried))
          {
            step = middle;
            fixed = tried;
          }
          else
          {
            failing = middle;
          }
        }
      }
      const double ratio = controlled.ms / fixed.ms;
      std::printf("%-24s %-16s %-13s %9.0e %9.2g %11.3g %7.2f %9llu %9llu %11.1f %11.3g %9.1f %7.2f\n", scene.name.c_str(),
        integratorName(c.integrator), judge, c.tolerance, allowed, controlled.error, controlled.error / allowed,
        controlled.steps, controlled.rejected, controlled.ms, step, fixed.ms, ratio);
      csv << scene.name << ',' << integratorName(c.integrator) << ',' << judge << ',' << c.tolerance << ',' << allowed << ','
          << controlled.error << ',' << controlled.steps << ',' << controlled.rejected << ',' << controlled.ms << ','
          << step << ',' << fixed.error << ',' << fixed.ms << ',' << ratio << '\n';
      char row[400];
      std::snprintf(row, sizeof row, "| %s | %s | %s | %.0e | %.2g | %.2g | %.2f | %llu (%llu) | %.0f | %.3g | %.0f | %.2f |\n",
        scene.name.c_str(), integratorName(c.integrator), judge, c.tolerance, allowed, controlled.error,
        controlled.error / allowed, controlled.steps, controlled.rejected, controlled.ms, step, fixed.ms, ratio);
      table << row;
      if (!controlled.ok)
      {
        std::printf("FAILED: %s, %s (%s) at %g: the error-controlled run did not finish\n", scene.name.c_str(),
          integratorName(c.integrator), judge, c.tolerance);
        status = 1;
      }
    }
  }
  return status;
}
