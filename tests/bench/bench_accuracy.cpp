// The accuracy and stability lab: run time against error on scenes with known
// answers, the largest stable step of each explicit integrator against the automatic estimate,
// and a stress matrix of hostile inputs.
//
// Scenes (each writes <out>/<scene>.csv with one row per run):
//   freefall     free fall for 0.5 s; error |z - (-g t^2 / 2)| / (g t^2 / 2) of the centroid.
//   bar          a bar (2 x 2 x 10 cells of 2 cm, E 1e5, nu 0.25, rho 1000) pinned at its top and
//                hanging: the static elongation rho g L^2 / (2 E). Model error: the network's
//                static answer (backward Euler run to rest) against it. Integration error of a
//                run: its elongation at t = 0.2 s against a converged reference (Midpoint at
//                1/16 and 1/32 of its automatic step, shown to agree), over rho g L^2 / (2 E).
//   cantilever   a beam (20 x 2 x 2 cells of 2 cm, E 2e7, nu 0.3, rho 1000) clamped at x = 0 and
//                sagging under its own weight: Timoshenko's tip sag q L^4 / (8 E I) + q L^2 /
//                (2 kappa G A), kappa = 5/6 (rectangle); the shear term is 1.0% of the bending
//                term at L / h = 10. Errors as for the bar, at t = 0.1 s.
//   restitution  PBD/XPBD: a flat sheet of linked particles dropped level from 10 cm with
//                restitution e = 0.5: rebound height of its lowest point e^2 h; and, every
//                method, a stiff tet cube (restitution_cube), measured against the same.
//   incline      every method: a block on a floor tilted by theta with friction mu: acceleration
//                g (sin theta - mu cos theta) (30 deg, mu 0.3) and sticking (20 deg, mu 0.5: tan
//                theta < mu; error = distance slid over the frictionless distance).
//   spot         a TetGen mesh of Keenan Crane's spot (38k tets, E 1e4) dropped 1 cm onto the
//                floor, 0.1 s: RMS distance to a converged Midpoint reference over the 0.2 m
//                bounding-box diagonal (skipped with a message when the file is absent).
//   frequency    omega_max of the stability meshes: Gershgorin bound and Lanczos estimates against
//                a converged value, and the estimate's cost (bench_accuracy_frequency.cpp).
//   jelly        the demo's jelly (data/jelly.vtu, 2,304 tets, the filter's default material)
//                dropped from 0.30 m, 0.4 s (lands at 0.25 s at 2.4 m/s and squashes): RMS distance
//                to Midpoint at 1/64 of its automatic step (1/32 of it agrees), over its diagonal.
//   stability    largest stable step of each explicit integrator by bisection on blow-up (from
//                small random velocities, fixed simulated time), against the automatic estimate.
//   stress       case x method -> finite / blow-up detected / refused; each cell in its own
//                process, bounded by steps and by an alarm, so a hang or a crash is seen.
//
// Usage: bench_accuracy [--quick] [--data DIR] [--out DIR] [scene ...]
// --quick runs reduced sweeps (about a minute) and checks: no NaN in any output, no crash or
// hang in the stress matrix, errors of the analytic scenes decreasing with the step; the exit
// status is 1 when a check fails.
#include "bench_accuracy_frequency.h"
#include "bench_meshes.h"

#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>
#include "bench_options.h"

#include "softbody/common/errors.h"
#include "softbody/stability/highest_frequency.h"
#include "softbody/massspring/mass_spring_forces.h"
#include "softbody/massspring/mass_spring_setup.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"
#include "softbody/pbd/pbd_simulation.h"

#include <tbb/global_control.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <sstream>
#include <thread>

using namespace softbody;

namespace
{

constexpr double kG = 9.81;
bool gQuick = false;
std::vector<std::string> gFailures; // checks that failed (quick mode fails the run on them)

void fail(const std::string& what)
{
  std::printf("CHECK FAILED: %s\n", what.c_str());
  gFailures.push_back(what);
}

struct Row
{
  std::string scene, method, solver;
  double step = 0.0;
  int iterations = 0, substeps = 0, threads = 1;
  double wall = 0.0;
  unsigned long long steps = 0;
  double error = 0.0;
  bool blewUp = false;
};

using SimPtr = std::unique_ptr<Simulation>;
using Measure = std::function<double(const Simulation&)>; // the scene's quantity

std::string number(double value, int digits = 6)
{
  char text[64];
  std::snprintf(text, sizeof text, "%.*g", digits, value);
  return text;
}

double seconds(std::chrono::steady_clock::duration d)
{
  return std::chrono::duration<double>(d).count();
}

Vec3 centroid(const std::vector<Vec3>& x)
{
  Vec3 c = Vec3::Zero();
  for (const Vec3& p : x)
  {
    c += p;
  }
  return c / double(x.size());
}

bool allFinite(const Simulation& sim)
{
  for (const Vec3& p : sim.positions())
  {
    if (!p.allFinite())
    {
      return false;
    }
  }
  for (const Vec3& v : sim.velocities())
  {
    if (!v.allFinite())
    {
      return false;
    }
  }
  for (double r : sim.tetVolumeRatios())
  {
    if (!std::isfinite(r))
    {
      return false;
    }
  }
  return true;
}

/// One timed run: make, advance to endTime (in `chunks` equal calls so a measure can watch the
/// trajectory), error = errorOf(sim). A detected divergence marks the row blown up.
Row timedRun(Row row, const std::function<SimPtr()>& make, double endTime,
  const std::function<double(const Simulation&)>& errorOf,
  const std::function<void(const Simulation&)>& watch = {}, int chunks = 1)
{
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, row.threads);
  SimPtr sim;
  auto start = std::chrono::steady_clock::now();
  try
  {
    sim = make();
    start = std::chrono::steady_clock::now();
    for (int c = 1; c <= chunks; ++c)
    {
      sim->advance(endTime * c / chunks);
      if (watch)
      {
        watch(*sim);
      }
    }
    row.wall = seconds(std::chrono::steady_clock::now() - start);
    row.steps = sim->stepCount();
    if (!allFinite(*sim))
    {
      fail(row.scene + " " + row.method + " " + row.solver + ": non-finite state without an error");
    }
    row.error = errorOf(*sim);
  }
  catch (const SimulationDivergedError&)
  {
    row.blewUp = true;
    row.error = std::numeric_limits<double>::infinity();
    row.wall = seconds(std::chrono::steady_clock::now() - start); // until the blow-up was caught
    row.steps = sim ? sim->stepCount() : 0;
  }
  if (!row.blewUp && !std::isfinite(row.error))
  {
    fail(row.scene + " " + row.method + " " + row.solver + ": error is not finite");
  }
  std::printf("  %-10s %-12s %-22s h %-10.4g it %3d sub %3d thr %d  %8.3f s %8llu steps  error %s\n",
    row.scene.c_str(), row.method.c_str(), row.solver.c_str(), row.step, row.iterations,
    row.substeps, row.threads, row.wall, row.steps,
    row.blewUp ? "BLEW UP" : number(row.error).c_str());
  std::fflush(stdout);
  return row;
}

void writeCsv(const std::string& path, const std::vector<Row>& rows)
{
  std::ofstream csv(path);
  csv << "scene,method,integrator_or_solver,step,iterations,substeps,threads,wall_seconds,steps,error,"
         "blew_up\n";
  for (const Row& r : rows)
  {
    csv << r.scene << ',' << r.method << ',' << r.solver << ',' << r.step << ',' << r.iterations
        << ',' << r.substeps << ',' << r.threads << ',' << r.wall << ',' << r.steps << ','
        << (r.blewUp ? std::string("inf") : number(r.error)) << ','
        << (r.blewUp ? "yes" : "no") << '\n';
  }
  std::printf("  wrote %s (%zu rows)\n", path.c_str(), rows.size());
}

// ------------------------------------------------------------------ scene description

/// A scene as both methods see it. The mass-spring body and scene, and the PBD body and
/// settings (XPBD with the same elasticity, PBD with stiffness 1); `quantity` reads the
/// measured value, `error` turns it into a relative error.
struct LabScene
{
  std::string name;
  double endTime = 0.1;
  bool massSpring = true;
  bool pbd = true;  ///< PBD (stiffness 1) rows
  bool xpbd = true; ///< XPBD (elasticity) rows
  Body body;
  SceneSettings scene;
  Body pbdBody;
  PbdSettings pbdSettings;
  std::function<double(const Simulation&)> error;
  /// For trajectory measures (rebound): a watcher per step and the final read-out.
  std::function<std::function<void(const Simulation&)>()> makeWatch;
  int watchChunks = 1;
  bool reduced = false; ///< a large mesh: fewer steps and splits (what a full run can afford)
};

Body pbdBodyOf(const Body& body)
{
  Body p;
  p.mesh.points = body.mesh.points;
  p.mesh.tets = body.mesh.tets;
  p.material.physical = body.material.physical; // density, and E and nu for XPBD
  p.pinned = body.pinned;
  return p;
}

PbdSettings pbdSettingsOf(const SceneSettings& scene, bool xpbd)
{
  PbdSettings s;
  s.formulation = xpbd ? PbdFormulation::Xpbd : PbdFormulation::Pbd;
  s.gravity = scene.gravity;
  s.floorEnabled = scene.floorEnabled;
  s.floor = scene.floor;
  s.reportConvergence = false;
  if (xpbd)
  {
    s.elasticFromMaterial = true;
  }
  return s;
}

SimPtr makeMassSpring(const LabScene& s, Integrator integrator, double h)
{
  SceneSettings scene = s.scene;
  scene.integrator = integrator;
  scene.timeStep = h;
  return std::make_unique<MassSpringSimulation>(s.body, scene);
}

SimPtr makePbd(const LabScene& s, bool xpbd, PbdSolver solver, double relaxation, double h, int iterations,
  int substeps)
{
  PbdSettings settings = s.pbdSettings;
  const PbdSettings defaults = pbdSettingsOf(s.scene, xpbd);
  settings.formulation = defaults.formulation;
  settings.elasticFromMaterial = defaults.elasticFromMaterial;
  settings.solver = solver;
  settings.relaxation = relaxation;
  settings.timeStep = h;
  settings.iterations = iterations;
  settings.substeps = substeps;
  return std::make_unique<PbdSimulation>(s.pbdBody, settings);
}

double automaticStep(const LabScene& s, Integrator integrator)
{
  SceneSettings scene = s.scene;
  scene.integrator = integrator;
  scene.timeStep = 0.0;
  const MassSpringSimulation sim(s.body, scene);
  return sim.stepSize();
}

const Integrator kExplicit[] = { Integrator::Euler, Integrator::Midpoint, Integrator::Verlet,
  Integrator::EulerCromer };

/// The sweep every scene gets: explicit integrators at multiples of their automatic step,
/// implicit ones at 1/60 s and finer, PBD/XPBD over iterations x substeps at equal budgets with
/// every solver, 1 and 2 threads where cheap.
std::vector<Row> sweep(const LabScene& s)
{
  std::vector<Row> rows;
  Row base;
  base.scene = s.name;
  const std::function<void(const Simulation&)> noWatch;
  auto run = [&](Row row, const std::function<SimPtr()>& make) {
    if (s.makeWatch)
    {
      auto watch = s.makeWatch();
      rows.push_back(timedRun(row, make, s.endTime, s.error, watch, s.watchChunks));
    }
    else
    {
      rows.push_back(timedRun(row, make, s.endTime, s.error));
    }
  };
  const bool small = gQuick || s.reduced;
  if (s.massSpring)
  {
    const std::vector<double> fractions = s.reduced ? std::vector<double>{ 2, 1 }
      : gQuick                                    ? std::vector<double>{ 2, 1, 0.5 }
                                                 : std::vector<double>{ 4, 2, 1, 0.5, 0.25 };
    for (Integrator integrator : kExplicit)
    {
      const double automatic = automaticStep(s, integrator);
      for (double f : fractions)
      {
        Row row = base;
        row.method = "mass-spring";
        row.solver = integratorName(integrator);
        row.step = f * automatic;
        run(row, [&] { return makeMassSpring(s, integrator, row.step); });
      }
      if (!gQuick && (!s.reduced || integrator == Integrator::EulerCromer))
      {
        Row row = base;
        row.method = "mass-spring";
        row.solver = integratorName(integrator);
        row.step = automatic;
        row.threads = 2;
        run(row, [&] { return makeMassSpring(s, integrator, row.step); });
      }
    }
    const std::vector<double> implicitSteps = small
      ? std::vector<double>{ 1.0 / 60, 1.0 / 240 }
      : std::vector<double>{ 1.0 / 60, 1.0 / 120, 1.0 / 240, 1.0 / 480, 1.0 / 960 };
    for (Integrator integrator : { Integrator::ImplicitEuler, Integrator::ProjectiveDynamics, Integrator::VertexBlockDescent })
    {
      for (double h : implicitSteps)
      {
        Row row = base;
        row.method = "mass-spring";
        row.solver = integratorName(integrator);
        row.step = h;
        run(row, [&] { return makeMassSpring(s, integrator, h); });
      }
    }
  }
  struct Split
  {
    int iterations, substeps;
  };
  const std::vector<std::vector<Split>> budgets = small
    ? std::vector<std::vector<Split>>{ { { 8, 1 }, { 2, 4 }, { 1, 8 } } }
    : std::vector<std::vector<Split>>{ { { 8, 1 }, { 2, 4 }, { 1, 8 } },
        { { 32, 1 }, { 4, 8 }, { 1, 32 } } };
  struct SolverCase
  {
    const char* name;
    PbdSolver solver;
    double relaxation;
  };
  const SolverCase solvers[] = { { "Gauss-Seidel", PbdSolver::GaussSeidel, 1.0 },
    { "SOR 1.5", PbdSolver::GaussSeidel, 1.5 }, { "Jacobi", PbdSolver::Jacobi, 1.0 },
    { "parallel Gauss-Seidel", PbdSolver::ParallelGaussSeidel, 1.0 } };
  for (bool xpbd : { false, true })
  {
    if ((xpbd && !s.xpbd) || (!xpbd && !s.pbd))
    {
      continue;
    }
    const double h = 1.0 / 60.0;
    for (const auto& budget : budgets)
    {
      for (const Split& split : budget)
      {
        for (const SolverCase& solver : solvers)
        {
          // Every split with Gauss-Seidel; the other solvers at the extremes of the smallest budget.
          const bool extreme = &budget == &budgets.front() && (split.substeps == 1 || split.iterations == 1);
          if (solver.solver != PbdSolver::GaussSeidel || solver.relaxation != 1.0)
          {
            if (!extreme || (small && solver.solver != PbdSolver::ParallelGaussSeidel))
            {
              continue;
            }
          }
          for (int threads : { 1, 2 })
          {
            if (threads == 2 && (gQuick || solver.solver == PbdSolver::GaussSeidel))
            {
              continue; // serial Gauss-Seidel runs on one thread anyway
            }
            Row row = base;
            row.method = xpbd ? "XPBD" : "PBD";
            row.solver = solver.name;
            row.step = h;
            row.iterations = split.iterations;
            row.substeps = split.substeps;
            row.threads = threads;
            run(row, [&] {
              return makePbd(s, xpbd, solver.solver, solver.relaxation, h, split.iterations, split.substeps);
            });
          }
        }
      }
    }
  }
  return rows;
}

/// Whether the rows of (method, solver) have errors that decrease as their step decreases (or
/// as substeps grow at a fixed total budget); rows that blew up are left out.
void checkDecreasing(const std::vector<Row>& rows, const std::string& method, const std::string& solver)
{
  std::vector<std::pair<double, double>> hv; // effective step, error
  for (const Row& r : rows)
  {
    if (r.method == method && r.solver == solver && !r.blewUp && r.threads == 1)
    {
      const double effective = r.substeps > 0 ? r.step / r.substeps : r.step;
      if (r.substeps > 0 && r.iterations * r.substeps != 8)
      {
        continue; // PBD: the budget-8 splits only
      }
      hv.emplace_back(effective, r.error);
    }
  }
  std::sort(hv.begin(), hv.end());
  for (std::size_t i = 1; i < hv.size(); ++i)
  {
    if (hv[i].second < 1e-9)
    {
      continue; // exact to rounding at the larger step too
    }
    if (!(hv[i - 1].second <= hv[i].second * 1.0001))
    {
      fail(rows.front().scene + " " + method + " " + solver + ": error " + std::to_string(hv[i - 1].second)
        + " at step " + std::to_string(hv[i - 1].first) + " is not below " + std::to_string(hv[i].second)
        + " at " + std::to_string(hv[i].first));
    }
  }
}

// ------------------------------------------------------------------ the scenes

std::vector<std::size_t> pointsWhere(const TetMesh& mesh, const std::function<bool(const Vec3&)>& test)
{
  std::vector<std::size_t> ids;
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
  {
    if (test(mesh.points[i]))
    {
      ids.push_back(i);
    }
  }
  return ids;
}

double meanDisplacement(const Simulation& sim, const std::vector<std::size_t>& ids, int axis)
{
  double sum = 0.0;
  for (std::size_t i : ids)
  {
    sum += sim.positions()[i][axis] - sim.restPositions()[i][axis];
  }
  return sum / double(ids.size());
}

LabScene freeFallScene()
{
  LabScene s;
  s.name = "freefall";
  s.endTime = 0.5;
  s.body.mesh = makeTetBox(2, 2, 2, 0.05, Vec3(0, 0, 1));
  s.pbdBody = pbdBodyOf(s.body);
  s.pbdSettings = pbdSettingsOf(s.scene, true);
  const double exact = 0.5 * kG * s.endTime * s.endTime;
  s.error = [exact](const Simulation& sim) {
    const Vec3 d = centroid(sim.positions()) - centroid(sim.restPositions());
    return std::abs(-d.z() - exact) / exact;
  };
  return s;
}

/// Runs backward Euler with large steps until the body rests: the network's static answer.
double staticAnswer(const LabScene& s, const std::function<double(const Simulation&)>& quantity)
{
  SceneSettings scene = s.scene;
  scene.integrator = Integrator::ImplicitEuler;
  scene.timeStep = 0.05;
  scene.implicit.tolerance = 1e-9;
  scene.implicit.maxIterations = 200;
  MassSpringSimulation sim(s.body, scene);
  double previous = 0.0, value = 0.0;
  for (int k = 1; k <= 200; ++k)
  {
    sim.advance(0.5 * k);
    value = quantity(sim);
    if (k > 4 && std::abs(value - previous) < 1e-9 * std::abs(value))
    {
      break;
    }
    previous = value;
  }
  return value;
}

/// A material model's static answer on a scene against elasticity's (the models table).
struct ModelAnswer
{
  std::string scene, model;
  std::size_t tets = 0;
  double answer = 0.0, analytic = 0.0;
};
std::vector<ModelAnswer> gModelAnswers;

/// XPBD's rest state with a continuum model: 10 iterations x 16 substeps of 1/120 s, damped to
/// rest over 3 s (its error falls with the square of the substep; methods.md).
double xpbdContinuumAnswer(const LabScene& s, MaterialModel model,
  const std::function<double(const Simulation&)>& quantity)
{
  Body body = s.pbdBody;
  body.material.massDistribution = MassDistribution::LumpedVolume;
  body.material.model = model;
  PbdSettings settings = pbdSettingsOf(s.scene, true);
  settings.iterations = 10;
  settings.substeps = 16;
  settings.damping = 5.0;
  PbdSimulation sim(body, settings);
  sim.advance(3.0);
  return quantity(sim);
}

/// Records the network's static answer and each continuum model's (the Static integrator, with
/// the finite-element mass lumping) on the scene's mesh; with `xpbdRows` also XPBD's rest state
/// of each continuum model.
void recordModelAnswers(const LabScene& s, double network, double analytic,
  const std::function<double(const Simulation&)>& quantity, bool xpbdRows = false)
{
  const std::size_t tets = s.body.mesh.tets.size();
  gModelAnswers.push_back({ s.name, materialModelName(MaterialModel::SpringNetwork), tets, network, analytic });
  // Both volumetric formulations: the nodal average is the remedy for locking, so its rows show
  // what it buys at these scenes' moderate nu, beside the per-tet element.
  for (VolumetricFormulation volumetric : { VolumetricFormulation::PerTet, VolumetricFormulation::NodalAverage })
  {
    for (MaterialModel model : { MaterialModel::Corotated, MaterialModel::StableNeoHookean })
    {
      Body body = s.body;
      body.material.model = model;
      body.material.volumetric = volumetric;
      body.material.massDistribution = MassDistribution::LumpedVolume;
      SceneSettings scene = s.scene;
      scene.integrator = Integrator::Static;
      scene.implicit.tolerance = 1e-10;
      MassSpringSimulation sim(body, scene);
      sim.advance(0.1);
      const std::string name = std::string(materialModelName(model))
        + (volumetric == VolumetricFormulation::NodalAverage ? " (Nodal Average)" : "");
      gModelAnswers.push_back({ s.name, name, tets, quantity(sim), analytic });
    }
  }
  if (!xpbdRows)
  {
    return;
  }
  for (MaterialModel model : { MaterialModel::Corotated, MaterialModel::StableNeoHookean })
  {
    gModelAnswers.push_back({ s.name, std::string("XPBD ") + materialModelName(model) + " (10 x 16 substeps)",
      tets, xpbdContinuumAnswer(s, model, quantity), analytic });
  }
}

/// The cantilever's static sag for each material model on meshes refined across the section
/// (2, 4 and 8 cells), against Timoshenko's beam: the continuum models converge (linear tets
/// lock in bending, so from far), the network does not (its stiffness is set by how the mesh
/// was cut). Fills gModelAnswers' rows "cantilever, N across".
void recordCantileverRefinement(const LabScene& s, double analytic, double cell, int cellsAcross,
  const std::function<double(const Simulation&)>& quantity)
{
  for (int refine : { 2, 4 })
  {
    const int across = cellsAcross * refine;
    LabScene fine = s;
    fine.name = "cantilever, " + std::to_string(across) + " across";
    const double fineCell = cell / refine;
    fine.body.mesh = makeTetBox(20 * refine, across, across, fineCell, Vec3(0, 0, 0.5));
    fine.body.pinned.assign(fine.body.mesh.points.size(), 0);
    for (std::size_t i : pointsWhere(fine.body.mesh, [](const Vec3& p) { return p.x() < 1e-9; }))
    {
      fine.body.pinned[i] = 1;
    }
    Body network = fine.body;
    SceneSettings scene = fine.scene;
    scene.integrator = Integrator::Static;
    scene.implicit.tolerance = 1e-10;
    MassSpringSimulation sim(network, scene);
    sim.advance(0.1);
    recordModelAnswers(fine, quantity(sim), analytic, quantity);
  }
}

std::string modelTable()
{
  std::string table = "| scene | tets | material model | static answer [m] | elasticity [m] | model error |\n"
                      "|---|---|---|---|---|---|\n";
  for (const ModelAnswer& a : gModelAnswers)
  {
    char line[256];
    std::snprintf(line, sizeof line, "| %s | %zu | %s | %.4e | %.4e | %+.1f%% |\n", a.scene.c_str(),
      a.tets, a.model.c_str(), a.answer, a.analytic, 100 * (a.answer - a.analytic) / a.analytic);
    table += line;
  }
  return table;
}

/// The converged dynamic reference: Midpoint at 1/16 and 1/32 of its automatic step; prints
/// how far apart they are and returns the finer one.
double convergedReference(const LabScene& s, const std::function<double(const Simulation&)>& quantity, double scale)
{
  const double automatic = automaticStep(s, Integrator::Midpoint);
  double values[2];
  const int divisors[2] = { gQuick ? 8 : 16, gQuick ? 16 : 32 };
  for (int k = 0; k < 2; ++k)
  {
    SimPtr sim = makeMassSpring(s, Integrator::Midpoint, automatic / divisors[k]);
    sim->advance(s.endTime);
    values[k] = quantity(*sim);
  }
  std::printf("  reference (Midpoint at automatic/%d and /%d): %.8g and %.8g, apart by %.2e of the "
              "scale: converged\n",
    divisors[0], divisors[1], values[0], values[1], std::abs(values[0] - values[1]) / scale);
  if (std::abs(values[0] - values[1]) / scale > 1e-3)
  {
    fail(s.name + ": the reference has not converged");
  }
  return values[1];
}

/// The period [s] of a body's swing, released from rest (its state at t = 0) and run for
/// `duration` with Midpoint at `stepFactor` of its automatic step: the time between the first two
/// maxima of `quantity` (each placed by a parabola through the three samples around it; samples
/// 1/800 of the duration apart). Only the first cycle: later ones beat (see the cantilever). 0 when
/// it peaks fewer than twice.
double swingPeriod(const LabScene& s, const std::function<double(const Simulation&)>& quantity,
  double duration, double stepFactor)
{
  SimPtr sim = makeMassSpring(s, Integrator::Midpoint, stepFactor * automaticStep(s, Integrator::Midpoint));
  constexpr int kSamples = 800;
  const double dt = duration / kSamples;
  std::vector<double> value{ quantity(*sim) };
  std::vector<double> peaks;
  for (int k = 1; k <= kSamples && peaks.size() < 2; ++k)
  {
    sim->advance(dt * k);
    value.push_back(quantity(*sim));
    const double a = value[k - 2 < 0 ? 0 : k - 2], b = value[k - 1], c = value[k];
    if (k >= 2 && b > a && b >= c)
    {
      // Vertex of the parabola through (-1, a), (0, b), (1, c), in samples from k - 1.
      const double offset = 0.5 * (a - c) / (a - 2 * b + c);
      peaks.push_back(dt * (k - 1 + offset));
    }
  }
  return peaks.size() < 2 ? 0.0 : peaks[1] - peaks[0];
}

struct ElasticScene
{
  LabScene scene;
  std::string summary; // model error line
};

ElasticScene barScene()
{
  LabScene s;
  s.name = "bar";
  s.endTime = 0.2;
  const double cell = 0.02, length = 10 * cell;
  s.body.mesh = makeTetBox(2, 2, 10, cell, Vec3(0, 0, 0));
  s.body.material.physical = { 1.0e5, 0.25, 1000.0, 1.0e-5 };
  s.body.pinned.assign(s.body.mesh.points.size(), 0);
  for (std::size_t i : pointsWhere(s.body.mesh, [&](const Vec3& p) { return p.z() > length - 1e-9; }))
  {
    s.body.pinned[i] = 1;
  }
  s.pbdBody = pbdBodyOf(s.body);
  s.pbdSettings = pbdSettingsOf(s.scene, true);
  s.pbd = false; // PBD's stiffness has no Young's modulus: no elastic answer to compare with
  const auto bottom = pointsWhere(s.body.mesh, [](const Vec3& p) { return p.z() < 1e-9; });
  const double E = 1.0e5, rho = 1000.0;
  const double analytic = rho * kG * length * length / (2 * E);
  auto elongation = [bottom](const Simulation& sim) { return -meanDisplacement(sim, bottom, 2); };
  const double network = staticAnswer(s, elongation);
  recordModelAnswers(s, network, analytic, elongation, true);
  char line[512];
  std::snprintf(line, sizeof line,
    "bar: elasticity rho g L^2/(2E) = %.4e m; the network's static answer (backward Euler to rest) "
    "%.4e m: model error %.1f%%",
    analytic, network, 100 * std::abs(network - analytic) / analytic);
  std::printf("  %s\n", line);
  const double reference = convergedReference(s, elongation, analytic);
  s.error = [=](const Simulation& sim) { return std::abs(elongation(sim) - reference) / analytic; };
  return { s, line };
}

ElasticScene cantileverScene()
{
  LabScene s;
  s.name = "cantilever";
  s.endTime = 0.1;
  const double cell = 0.02, L = 20 * cell, h = 2 * cell;
  const double E = 2.0e7, nu = 0.3, rho = 1000.0;
  s.body.mesh = makeTetBox(20, 2, 2, cell, Vec3(0, 0, 0.5));
  s.body.material.physical = { E, nu, rho, 1.0e-5 };
  s.body.pinned.assign(s.body.mesh.points.size(), 0);
  for (std::size_t i : pointsWhere(s.body.mesh, [](const Vec3& p) { return p.x() < 1e-9; }))
  {
    s.body.pinned[i] = 1;
  }
  s.pbdBody = pbdBodyOf(s.body);
  s.pbdSettings = pbdSettingsOf(s.scene, true);
  s.pbd = false;
  const auto tip = pointsWhere(s.body.mesh, [&](const Vec3& p) { return p.x() > L - 1e-9; });
  const double A = h * h, I = h * h * h * h / 12, q = rho * A * kG, G = E / (2 * (1 + nu)), kappa = 5.0 / 6;
  const double bending = q * L * L * L * L / (8 * E * I), shear = q * L * L / (2 * kappa * G * A);
  const double analytic = bending + shear;
  auto sag = [tip](const Simulation& sim) { return -meanDisplacement(sim, tip, 2); };
  const double network = staticAnswer(s, sag);
  recordModelAnswers(s, network, analytic, sag, true);
  // The tip's points, found again on each refined mesh (x = L), measure the same sag.
  recordCantileverRefinement(s, analytic, cell, 2, [L](const Simulation& sim) {
    double drop = 0.0;
    int count = 0;
    for (std::size_t i = 0; i < sim.restPositions().size(); ++i)
    {
      if (sim.restPositions()[i].x() > L - 1e-9)
      {
        drop += sim.restPositions()[i].z() - sim.positions()[i].z();
        ++count;
      }
    }
    return drop / count;
  });
  const double period = 2 * M_PI * L * L / (1.875 * 1.875) * std::sqrt(rho * A / (E * I));
  // The first bending period of the network, measured: released from its rest shape, the beam
  // swings about its static sag; at the automatic step and at half of it (converged in the step).
  // The square section's two bending modes have nearly equal periods and the Kuhn split's
  // diagonals couple them: the vertical swing turns into a sideways one and back (beats, the tip
  // swinging up to 8.7 mm sideways by 0.39 s), so only the first cycle is timed.
  const double measured = swingPeriod(s, sag, 2.0 * period, 1.0);
  const double measuredHalf = swingPeriod(s, sag, 2.0 * period, 0.5);
  if (!(std::abs(measured - measuredHalf) < 1e-3 * measuredHalf))
  {
    fail("cantilever: the measured period changes with the step: " + number(measured) + " s and " +
      number(measuredHalf) + " s");
  }
  // Rayleigh: omega^2 ~ g / (static sag), so a model as much too stiff in bending as its sag is
  // too small has a period sqrt(network / bending) of elasticity's (the sag compared with the
  // Euler-Bernoulli term, the one the period formula is for).
  const double impliedByTheSag = period * std::sqrt(network / bending);
  if (!(std::abs(measuredHalf / impliedByTheSag - 1.0) < 0.1))
  {
    fail("cantilever: the measured period " + number(measuredHalf) + " s is not what the static sag implies, " +
      number(impliedByTheSag) + " s (mass or stiffness inconsistent between statics and dynamics)");
  }
  char line[1024];
  std::snprintf(line, sizeof line,
    "cantilever: Euler-Bernoulli q L^4/(8EI) = %.4e m + shear q L^2/(2 kappa G A) = %.4e m "
    "(kappa 5/6) = %.4e m; the network's static answer %.4e m: model error %.1f%%. First bending "
    "period 2 pi L^2/1.875^2 sqrt(rho A/(EI)) = %.4f s; the network's, measured (between the tip's "
    "first two lowest points, Midpoint at the automatic step and half of it: %.5f and %.5f s) %.4f s: model "
    "error %.1f%% (what its static sag implies: %.4f s)",
    bending, shear, analytic, network, 100 * std::abs(network - analytic) / analytic, period,
    measured, measuredHalf, measuredHalf, 100 * (measuredHalf - period) / period, impliedByTheSag);
  std::printf("  %s\n", line);
  const double reference = convergedReference(s, sag, analytic);
  s.error = [=](const Simulation& sim) { return std::abs(sag(sim) - reference) / analytic; };
  return { s, line };
}

/// A flat 3 x 3 sheet of linked particles falling level (every particle touches at once: PBD's
/// restitution is a per-particle velocity rule, so e^2 h is its answer) or, with `cube`, a stiff tet cube, where the constraints share
/// the bottom layer's bounce with the layers above (no closed form; reported against e^2 h).
LabScene restitutionScene(bool cube)
{
  LabScene s;
  s.name = cube ? "restitution_cube" : "restitution";
  const double h0 = 0.1, e = 0.5;
  s.endTime = 0.3;
  s.massSpring = cube; // the sheet of particles is PBD's alone
  s.body.mesh = makeTetBox(2, 2, 2, 0.02, Vec3(0, 0, h0));
  s.body.material.physical.youngsModulus = 1e7; // stiff: the bounce is the body's, not a wobble
  s.scene.floorEnabled = true;
  s.pbdBody = pbdBodyOf(s.body);
  if (!cube)
  {
    s.pbdBody = Body{};
    for (int i = 0; i < 3; ++i)
    {
      for (int j = 0; j < 3; ++j)
      {
        s.pbdBody.mesh.points.push_back(Vec3(0.02 * i, 0.02 * j, h0));
      }
    }
    for (int i = 0; i < 3; ++i)
    {
      for (int j = 0; j < 3; ++j)
      {
        if (i < 2)
        {
          s.pbdBody.links.push_back({ 3 * i + j, 3 * (i + 1) + j });
        }
        if (j < 2)
        {
          s.pbdBody.links.push_back({ 3 * i + j, 3 * i + j + 1 });
        }
      }
    }
    s.pbdBody.pointMass.assign(9, 0.01);
  }
  s.pbdSettings = pbdSettingsOf(s.scene, true);
  s.pbdSettings.collisions.restitution = e;
  // Bodies rest a contact margin (plus a particle's radius) above the floor: a stated margin, so
  // heights are measured from where the body rests, and the drop is h0 less that.
  s.pbdSettings.collisions.margin = 1e-3;
  s.scene.collisions.margin = 1e-3;
  s.scene.collisions.restitution = e;
  const double rest = (cube ? 0.0 : s.pbdSettings.particleRadius) + s.pbdSettings.collisions.margin;
  // The apex of the lowest point after the first contact, watched at every 1/480 s.
  auto apex = std::make_shared<double>(0.0);
  auto landed = std::make_shared<bool>(false);
  s.watchChunks = 144;
  s.makeWatch = [apex, landed, rest]() -> std::function<void(const Simulation&)> {
    *apex = 0.0;
    *landed = false;
    return [apex, landed, rest](const Simulation& sim) {
      double low = std::numeric_limits<double>::infinity();
      for (const Vec3& p : sim.positions())
      {
        low = std::min(low, p.z());
      }
      if (low < rest + 1e-3)
      {
        *landed = true;
      }
      if (*landed)
      {
        *apex = std::max(*apex, low - rest);
      }
    };
  };
  const double exact = e * e * (h0 - rest);
  s.error = [apex, exact](const Simulation&) { return std::abs(*apex - exact) / exact; };
  return s;
}

LabScene inclineScene(double thetaDegrees, double mu, bool sticks)
{
  LabScene s;
  s.name = sticks ? "incline_stick" : "incline_slide";
  s.endTime = 0.5;
  const double theta = thetaDegrees * M_PI / 180, c = std::cos(theta), sn = std::sin(theta);
  Eigen::Matrix3d R;
  R << c, 0, sn, 0, 1, 0, -sn, 0, c;
  s.body.mesh = makeTetBox(2, 2, 1, 0.05, Vec3(-0.05, -0.05, 1e-6));
  for (Vec3& p : s.body.mesh.points)
  {
    p = R * p;
  }
  s.body.material.physical.youngsModulus = 1e7;
  s.scene.floorEnabled = true;
  s.scene.floor.normal = R * Vec3(0, 0, 1);
  s.pbdBody = pbdBodyOf(s.body);
  s.pbdSettings = pbdSettingsOf(s.scene, true);
  s.pbdSettings.collisions.staticFriction = mu;
  s.pbdSettings.collisions.dynamicFriction = mu;
  s.scene.collisions.staticFriction = mu;
  s.scene.collisions.dynamicFriction = mu;
  const Vec3 down = R * Vec3(1, 0, 0);
  const double T = s.endTime;
  const double a = kG * (sn - mu * c);
  s.error = [=](const Simulation& sim) {
    const double slid = (centroid(sim.positions()) - centroid(sim.restPositions())).dot(down);
    if (sticks)
    {
      return std::abs(slid) / (0.5 * kG * sn * T * T);
    }
    return std::abs(2 * slid / (T * T) - a) / a;
  };
  return s;
}

double rmsOverDiagonal(const std::vector<Vec3>& a, const std::vector<Vec3>& b, double diagonal)
{
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    sum += (a[i] - b[i]).squaredNorm();
  }
  return std::sqrt(sum / double(a.size())) / diagonal;
}

/// A body dropped onto the floor: scenes without a closed form, measured against a converged
/// reference (Midpoint at two fractions of its automatic step, shown to agree).
struct DropSpec
{
  const char* name;
  const char* what;      ///< the mesh and where it starts, for the log
  double endTime;        ///< [s]
  int divisors[2];       ///< the reference: Midpoint at these fractions of its automatic step
  double youngsModulus;  ///< [Pa]
  double dampingTime;    ///< [s]
};

/// A public surface meshed by TetGen (default quality), scaled to a 0.2 m diagonal, its lowest
/// point `drop` above the floor. Empty, with a note, when the file is absent.
TetMesh publicSurfaceBody(const std::string& path, const std::string& dataDir, double drop, std::string& note)
{
  if (!std::filesystem::exists(path))
  {
    note = path + " not found; scene skipped";
    return {};
  }
  TetMesh mesh = bench::meshFromSpec(path, dataDir).mesh;
  Vec3 lo = mesh.points[0], hi = mesh.points[0];
  for (const Vec3& p : mesh.points)
  {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double scale = 0.2 / (hi - lo).norm();
  for (Vec3& p : mesh.points)
  {
    p = (p - lo) * scale + Vec3(0, 0, drop);
  }
  return mesh;
}

/// The demo's jelly (data/jelly.vtu, as committed: its bottom 0.30 m above the floor).
TetMesh demoJelly(const std::string& path, std::string& note)
{
  if (!std::filesystem::exists(path))
  {
    note = path + " not found; scene skipped";
    return {};
  }
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  TetMesh mesh;
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i)
  {
    const double* p = grid->GetPoint(i);
    mesh.points.emplace_back(p[0], p[1], p[2]);
  }
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    grid->GetCellPoints(c, ids);
    mesh.tets.push_back({ std::int32_t(ids->GetId(0)), std::int32_t(ids->GetId(1)),
      std::int32_t(ids->GetId(2)), std::int32_t(ids->GetId(3)) });
  }
  return mesh;
}

bool meshDropScene(const DropSpec& d, TetMesh mesh, LabScene& s, std::string& note)
{
  if (mesh.tets.empty())
  {
    note = std::string(d.name) + ": " + note;
    std::printf("  %s\n", note.c_str());
    return false;
  }
  Vec3 lo = mesh.points[0], hi = mesh.points[0];
  for (const Vec3& p : mesh.points)
  {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double diagonal = (hi - lo).norm(); // errors are RMS distances over it
  s.name = d.name;
  s.endTime = d.endTime;
  s.reduced = mesh.tets.size() > 10000;
  s.body.mesh = mesh;
  s.body.material.physical.youngsModulus = d.youngsModulus;
  s.body.material.physical.dampingTime = d.dampingTime;
  s.scene.floorEnabled = true;
  s.pbdBody = pbdBodyOf(s.body);
  s.pbdSettings = pbdSettingsOf(s.scene, true);
  s.pbd = false;
  std::printf("  %s: %zu points, %zu tets, %s, E %.3g Pa, damping time %.3g s, %.3g s\n", d.name,
    mesh.points.size(), mesh.tets.size(), d.what, d.youngsModulus, d.dampingTime, d.endTime);
  const double automatic = automaticStep(s, Integrator::Midpoint);
  std::printf("  %s: automatic Midpoint step %.3g s\n", d.name, automatic);
  std::fflush(stdout);
  std::vector<Vec3> refs[2];
  for (int k = 0; k < 2; ++k)
  {
    SimPtr sim = makeMassSpring(s, Integrator::Midpoint, automatic / d.divisors[k]);
    sim->advance(s.endTime);
    refs[k] = sim->positions();
  }
  const double apart = rmsOverDiagonal(refs[0], refs[1], diagonal);
  const std::string which = "Midpoint at 1/" + std::to_string(d.divisors[0]) + " and 1/" +
    std::to_string(d.divisors[1]) + " of its automatic step";
  std::printf("  reference (%s): RMS apart %.2e of the diagonal\n", which.c_str(), apart);
  note = std::string(d.name) + ": reference " + which + ", apart by " + number(apart, 3) +
    " (RMS over the " + number(diagonal, 3) + " m diagonal); the finer one is the reference";
  if (!(apart < 1e-3))
  {
    fail(std::string(d.name) + ": the reference has not converged");
  }
  auto reference = std::make_shared<std::vector<Vec3>>(refs[1]);
  s.error = [reference, diagonal](const Simulation& sim) {
    return rmsOverDiagonal(sim.positions(), *reference, diagonal);
  };
  return true;
}

// ------------------------------------------------------------------ fastest per target

std::string fastestTable(const std::map<std::string, std::vector<Row>>& byScene)
{
  std::ostringstream md;
  md << "| scene | 10% error | 1% error | 0.1% error |\n|---|---|---|---|\n";
  for (const auto& [scene, rows] : byScene)
  {
    md << "| " << scene;
    for (double target : { 0.1, 0.01, 0.001 })
    {
      const Row* best = nullptr;
      for (const Row& r : rows)
      {
        if (!r.blewUp && r.error <= target && (!best || r.wall < best->wall))
        {
          best = &r;
        }
      }
      char cell[256];
      if (!best)
      {
        std::snprintf(cell, sizeof cell, "none reached");
      }
      else if (best->substeps > 0)
      {
        std::snprintf(cell, sizeof cell, "%s %s, %d it x %d sub, %.3g ms (err %.2g)", best->method.c_str(),
          best->solver.c_str(), best->iterations, best->substeps, 1e3 * best->wall, best->error);
      }
      else
      {
        std::snprintf(cell, sizeof cell, "%s, h %.3g s, %.3g ms (err %.2g)", best->solver.c_str(), best->step,
          1e3 * best->wall, best->error);
      }
      md << " | " << cell;
    }
    md << " |\n";
  }
  return md.str();
}

/// Substeps against iterations at equal budget: for each scene and PBD/XPBD Gauss-Seidel budget,
/// the error of every split.
std::string substepTable(const std::map<std::string, std::vector<Row>>& byScene)
{
  std::ostringstream md;
  md << "| scene | method | budget | it x sub: error |\n|---|---|---|---|\n";
  for (const auto& [scene, rows] : byScene)
  {
    for (const std::string method : { "PBD", "XPBD" })
    {
      std::map<int, std::string> cells;
      for (const Row& r : rows)
      {
        if (r.method == method && r.solver == "Gauss-Seidel" && r.threads == 1)
        {
          char c[96];
          std::snprintf(c, sizeof c, "%dx%d: %s; ", r.iterations, r.substeps,
            r.blewUp ? "blew up" : number(r.error, 3).c_str());
          cells[r.iterations * r.substeps] += c;
        }
      }
      for (const auto& [budget, text] : cells)
      {
        md << "| " << scene << " | " << method << " | " << budget << " | " << text << " |\n";
      }
    }
  }
  return md.str();
}

// ------------------------------------------------------------------ stability table

/// Whether `steps` steps of h from rest with small random velocities (no gravity, no floor)
/// multiply the energy by more than 1000 or are caught diverging.
bool blowsUp(const Body& body, SceneSettings scene, double h, double endTime)
{
  scene.timeStep = h;
  scene.gravity = Vec3::Zero();
  scene.floorEnabled = false;
  MassSpringSimulation sim(body, scene);
  DynamicState start = sim.state();
  std::mt19937 random(7);
  std::uniform_real_distribution<double> u(-1e-3, 1e-3);
  for (Vec3& v : start.velocities)
  {
    v = Vec3(u(random), u(random), u(random));
  }
  sim.restoreState(start);
  auto energy = [&] { return sim.mechanicalEnergy(); };
  const double e0 = energy();
  try
  {
    sim.advance(endTime);
  }
  catch (const SimulationDivergedError&)
  {
    return true;
  }
  return !(energy() < 1e3 * e0);
}

std::string stabilityTable(const std::string& dataDir, const std::string& out)
{
  const std::vector<bench::NamedMesh> meshes = bench::stabilityMeshes(dataDir, gQuick);
  std::ofstream csv(out + "/stability.csv");
  csv << "mesh,points,tets,integrator,automatic_step,estimated_limit,bisected_limit,simulated_time,"
         "automatic_over_limit,safe\n";
  std::ostringstream md;
  md << "| mesh | points | tets | integrator | automatic step [ms] | bisected limit [ms] | automatic / limit |\n"
        "|---|---|---|---|---|---|---|\n";
  const int iterations = gQuick ? 5 : 9;
  // The spring network at the default and the thesis's damping; Corotated (whose automatic
  // step rests on the same Lanczos estimate, on linear elasticity) at the default.
  const std::pair<MaterialModel, bool> variants[] = { { MaterialModel::SpringNetwork, false },
    { MaterialModel::SpringNetwork, true }, { MaterialModel::Corotated, false } };
  for (const auto& named : meshes)
  for (const auto& [model, thesisDamping] : variants)
  {
    Body body;
    body.mesh = named.mesh;
    body.material.model = model;
    // Default material: E 1e5 Pa, nu 0.3, rho 1100 kg/m^3, damping time 2 ms, which over-damps
    // the highest modes (beta omega_max >> 2): there every integrator's limit is ~2 / (beta
    // omega^2) and all four are alike. The thesis's Table 6.1 (Euler 3.0 < Midpoint 3.5 < Verlet
    // 6.5 = Euler-Cromer 6.5 ms) implies under-damped top modes: Euler is stable up to h = beta
    // and Verlet to ~2 / omega, so Euler / Verlet = beta omega / 2 = 3.0 / 6.5 is the top mode's
    // damping ratio. The "thesis damping" rows set beta = 2 x 0.46 / omega_max.
    std::string label = named.name + (model == MaterialModel::SpringNetwork ? "" : std::string(", ") + materialModelName(model));
    if (thesisDamping)
    {
      // omega_max itself (the Lanczos estimate, converged on these meshes: the frequency
      // table), not the set-up's, which carries a margin for deformation.
      const MassSpringSetup probe = prepareMassSpring(body, SceneSettings{});
      const double omegaMax = lanczosFrequencyEstimate(probe.topology, probe.constants,
        probe.masses.inverseMass, probe.mesh.points, kFrequencyLanczosSteps).upperOmega;
      body.material.physical.dampingTime = 2 * 0.46 / omegaMax;
      char text[128];
      std::snprintf(text, sizeof text, " (beta %.3g ms)", 1e3 * body.material.physical.dampingTime);
      label += text;
    }
    else
    {
      label += " (beta 2 ms)";
    }
    SceneSettings ec;
    ec.integrator = Integrator::EulerCromer;
    double endTime = 0.0;
    try
    {
      endTime = 1000 * MassSpringSimulation(body, ec).stepSize();
    }
    catch (const std::exception& e)
    {
      std::printf("  stability: %s refused (%s)\n", label.c_str(), e.what());
      continue;
    }
    for (Integrator integrator : kExplicit)
    {
      SceneSettings scene;
      scene.integrator = integrator;
      const MassSpringSimulation automatic(body, scene);
      const double h = automatic.stepSize();
      const auto start = std::chrono::steady_clock::now();
      double lo = h, hi = 16 * h;
      if (blowsUp(body, scene, h, endTime))
      {
        lo = h / 16;
        hi = h;
        fail("stability: the automatic step blows up on " + label + " with " + integratorName(integrator));
      }
      else if (!blowsUp(body, scene, hi, endTime))
      {
        lo = hi; // stable even at 16x: a lower bound only
      }
      for (int k = 0; k < iterations && lo < hi; ++k)
      {
        const double mid = std::sqrt(lo * hi);
        (blowsUp(body, scene, mid, endTime) ? hi : lo) = mid;
      }
      const double ratio = h / lo;
      std::printf("  stability %-50s %-12s automatic %.4g ms  limit %.4g ms  ratio %.3f  (%.1f s)\n",
        label.c_str(), integratorName(integrator), 1e3 * h, 1e3 * lo, ratio,
        seconds(std::chrono::steady_clock::now() - start));
      std::fflush(stdout);
      csv << label << ',' << named.mesh.points.size() << ',' << named.mesh.tets.size() << ','
          << integratorName(integrator) << ',' << h << ',' << automatic.estimatedStableStep() << ',' << lo
          << ',' << endTime << ',' << ratio << ',' << (ratio <= 1.0 ? "yes" : "no") << '\n';
      char line[512];
      std::snprintf(line, sizeof line, "| %s | %zu | %zu | %s | %.4g | %.4g | %.3f |\n", label.c_str(),
        named.mesh.points.size(), named.mesh.tets.size(), integratorName(integrator), 1e3 * h, 1e3 * lo, ratio);
      md << line;
    }
  }
  return md.str();
}

// ------------------------------------------------------------------ stress matrix

const char* kStressCases[] = { "step 10x past stable", "stretched 16x", "perturbed 10-50% of edge",
  "inverted tets", "flat tet", "E 1e2 Pa", "E 1e12 Pa", "nu 0.49", "density 1", "density 1e5",
  "all pinned", "zero-mass point" };
const char* kStressMethods[] = { "Euler", "Midpoint", "Verlet", "Euler-Cromer", "Implicit Euler",
  "Projective Dynamics", "PBD", "XPBD" };

/// Runs one cell in this process and prints "OUTCOME <word> <detail>".
int runStressCell(int caseIndex, int methodIndex)
{
  const std::string c = kStressCases[caseIndex];
  const int m = methodIndex;
  const bool isPbd = m >= 6, isXpbd = m == 7;
  Body body;
  body.mesh = makeTetBox(3, 3, 3, 0.05, Vec3(0, 0, 0.02));
  SceneSettings scene;
  const Integrator integrators[] = { Integrator::Euler, Integrator::Midpoint, Integrator::Verlet,
    Integrator::EulerCromer, Integrator::ImplicitEuler, Integrator::ProjectiveDynamics };
  scene.floorEnabled = true;
  if (!isPbd)
  {
    scene.integrator = integrators[m];
  }
  double endTime = 0.25;
  double meanEdge = 0.05 * (1 + std::sqrt(2.0) * 2 + std::sqrt(3.0)) / 4;
  std::function<void(DynamicState&)> startState;
  double stepFactor = 0.0;
  if (c == "step 10x past stable")
  {
    stepFactor = 10.0;
  }
  else if (c == "stretched 16x")
  {
    startState = [](DynamicState& s) {
      const Vec3 c0 = centroid(s.positions);
      for (Vec3& p : s.positions)
      {
        p = c0 + 16.0 * (p - c0);
      }
    };
  }
  else if (c == "perturbed 10-50% of edge")
  {
    startState = [meanEdge](DynamicState& s) {
      std::mt19937 random(11);
      std::uniform_real_distribution<double> size(0.1, 0.5);
      std::normal_distribution<double> n;
      for (Vec3& p : s.positions)
      {
        const Vec3 d(n(random), n(random), n(random));
        p += size(random) * meanEdge * d.normalized();
      }
    };
  }
  else if (c == "inverted tets")
  {
    for (std::size_t t = 0; t < body.mesh.tets.size(); t += 5)
    {
      std::swap(body.mesh.tets[t][0], body.mesh.tets[t][1]);
    }
  }
  else if (c == "flat tet")
  {
    const auto n = std::int32_t(body.mesh.points.size());
    body.mesh.points.push_back(Vec3(1, 0, 0.5));
    body.mesh.points.push_back(Vec3(1.1, 0, 0.5));
    body.mesh.points.push_back(Vec3(1, 0.1, 0.5));
    body.mesh.points.push_back(Vec3(1.1, 0.1, 0.5));
    body.mesh.tets.push_back({ n, n + 1, n + 2, n + 3 });
  }
  else if (c == "E 1e2 Pa")
  {
    body.material.physical.youngsModulus = 1e2;
  }
  else if (c == "E 1e12 Pa")
  {
    body.material.physical.youngsModulus = 1e12;
  }
  else if (c == "nu 0.49")
  {
    body.material.physical.poissonRatio = 0.49;
  }
  else if (c == "density 1")
  {
    body.material.physical.density = 1.0;
  }
  else if (c == "density 1e5")
  {
    body.material.physical.density = 1e5;
  }
  else if (c == "all pinned")
  {
    body.pinned.assign(body.mesh.points.size(), 1);
  }
  else if (c == "zero-mass point")
  {
    body.mesh.points.push_back(Vec3(1, 1, 1)); // in no tet: no volume, no mass
  }
  if (m == 6 && (c.rfind("E ", 0) == 0 || c == "nu 0.49"))
  {
    std::printf("OUTCOME n/a PBD takes a stiffness in [0, 1], not E or nu\n");
    return 0;
  }
  const auto start = std::chrono::steady_clock::now();
  try
  {
    SimPtr sim;
    if (isPbd)
    {
      Body p = pbdBodyOf(body);
      PbdSettings s = pbdSettingsOf(scene, isXpbd);
      s.timeStep = stepFactor > 0 ? stepFactor / 60.0 : 1.0 / 60.0;
      sim = std::make_unique<PbdSimulation>(p, s);
    }
    else
    {
      if (stepFactor > 0)
      {
        if (isImplicit(scene.integrator))
        {
          scene.timeStep = stepFactor / 60.0; // no stability limit: ten frames per step
        }
        else
        {
          SceneSettings probe = scene;
          const MassSpringSimulation automatic(body, probe);
          scene.timeStep = stepFactor * automatic.estimatedStableStep();
        }
      }
      else if (isImplicit(scene.integrator))
      {
        scene.timeStep = 1.0 / 60.0; // one step per frame, as the filter runs them
      }
      sim = std::make_unique<MassSpringSimulation>(body, scene);
    }
    // Bounded by steps: at most 20,000 steps whatever the step size.
    endTime = std::min(endTime, 20000 * sim->stepSize());
    if (startState)
    {
      DynamicState s = sim->state();
      startState(s);
      sim->restoreState(s);
    }
    sim->advance(endTime);
    const double wall = seconds(std::chrono::steady_clock::now() - start);
    if (!allFinite(*sim))
    {
      std::printf("OUTCOME NaN non-finite output without an error after %.3f s\n", wall);
      return 0;
    }
    std::printf("OUTCOME finite %llu steps to t = %.3g s, %.3f s wall%s\n", sim->stepCount(), sim->time(), wall,
      sim->warnings().empty() ? "" : (" (warning: " + sim->warnings().front().substr(0, 80) + ")").c_str());
  }
  catch (const SimulationDivergedError& e)
  {
    std::printf("OUTCOME blow-up %s\n", std::string(e.what()).substr(0, 120).c_str());
  }
  catch (const InvalidInputError& e)
  {
    std::printf("OUTCOME refused %s\n", std::string(e.what()).substr(0, 120).c_str());
  }
  catch (const std::exception& e)
  {
    std::printf("OUTCOME other-exception %s\n", e.what());
  }
  return 0;
}

struct CellResult
{
  std::string outcome, detail;
  double wall = 0.0;
};

/// The cell in a child process (this program with --stress-cell), killed after `limit` seconds.
CellResult spawnStressCell(int caseIndex, int methodIndex, unsigned limit)
{
  int pipeFds[2];
  if (pipe(pipeFds) != 0)
  {
    return { "crash", "pipe() failed", 0.0 };
  }
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid == 0)
  {
    dup2(pipeFds[1], STDOUT_FILENO);
    close(pipeFds[0]);
    alarm(limit);
    const std::string a = std::to_string(caseIndex), b = std::to_string(methodIndex);
    execl("/proc/self/exe", "bench_accuracy", "--stress-cell", a.c_str(), b.c_str(), (char*)nullptr);
    _exit(127);
  }
  close(pipeFds[1]);
  std::string text;
  char buffer[4096];
  ssize_t n;
  while ((n = read(pipeFds[0], buffer, sizeof buffer)) > 0)
  {
    text.append(buffer, std::size_t(n));
  }
  close(pipeFds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  CellResult r;
  r.wall = seconds(std::chrono::steady_clock::now() - start);
  if (WIFSIGNALED(status))
  {
    const int sig = WTERMSIG(status);
    r.outcome = sig == SIGALRM ? "hang" : "crash";
    r.detail = "signal " + std::to_string(sig);
    return r;
  }
  const auto at = text.find("OUTCOME ");
  if (at == std::string::npos || WEXITSTATUS(status) != 0)
  {
    r.outcome = "crash";
    r.detail = "exit status " + std::to_string(WEXITSTATUS(status));
    return r;
  }
  std::istringstream line(text.substr(at + 8));
  line >> r.outcome;
  std::getline(line, r.detail);
  return r;
}

std::string csvQuote(std::string s)
{
  std::replace(s.begin(), s.end(), '"', '\'');
  return "\"" + s + "\"";
}

std::string stressMatrix(const std::string& out)
{
  std::ofstream csv(out + "/stress.csv");
  csv << "case,method,outcome,wall_seconds,detail\n";
  std::ostringstream md;
  md << "| case |";
  for (const char* m : kStressMethods)
  {
    md << ' ' << m << " |";
  }
  md << "\n|---|";
  for (std::size_t i = 0; i < std::size(kStressMethods); ++i)
  {
    md << "---|";
  }
  md << '\n';
  std::map<std::string, int> counts;
  const std::map<std::string, std::string> words = { { "finite", "finite" },
    { "blow-up", "blow-up detected (SimulationDivergedError)" }, { "refused", "refused (InvalidInputError)" },
    { "n/a", "n/a" } };
  for (std::size_t c = 0; c < std::size(kStressCases); ++c)
  {
    md << "| " << kStressCases[c] << " |";
    for (std::size_t m = 0; m < std::size(kStressMethods); ++m)
    {
      const CellResult r = spawnStressCell(int(c), int(m), 60);
      counts[r.outcome]++;
      std::printf("  stress %-26s %-20s %-10s %.2f s %s\n", kStressCases[c], kStressMethods[m], r.outcome.c_str(),
        r.wall, r.detail.c_str());
      std::fflush(stdout);
      csv << csvQuote(kStressCases[c]) << ',' << kStressMethods[m] << ',' << r.outcome << ',' << r.wall << ','
          << csvQuote(r.detail) << '\n';
      const auto w = words.find(r.outcome);
      md << ' ' << (w == words.end() ? "**" + r.outcome + " (bug)**" : r.outcome) << " |";
      if (w == words.end())
      {
        fail("stress: " + std::string(kStressCases[c]) + " x " + kStressMethods[m] + ": " + r.outcome + " "
          + r.detail);
      }
    }
    md << '\n';
  }
  md << "\nOutcome counts:";
  for (const auto& [k, n] : counts)
  {
    md << ' ' << k << ' ' << n << ';';
  }
  md << "\n";
  return md.str();
}

} // namespace

int main(int argc, char** argv)
{
  std::setvbuf(stdout, nullptr, _IOLBF, 0); // line-buffered, also into a pipe or a file
  bench::Options options;
  options.csv = "output/bench";
  std::set<std::string> scenes;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "--stress-cell" && i + 2 < argc)
    {
      return runStressCell(std::atoi(argv[i + 1]), std::atoi(argv[i + 2]));
    }
    if (arg == "--quick" || arg == "--smoke")
    {
      gQuick = true;
    }
    else if (arg == "--data" && i + 1 < argc)
    {
      options.dataDir = argv[++i];
    }
    else if ((arg == "--out" || arg == "--csv") && i + 1 < argc)
    {
      options.csv = argv[++i];
    }
    else if (arg.rfind("--", 0) != 0)
    {
      scenes.insert(arg);
    }
    else
    {
      std::fprintf(stderr, "usage: bench_accuracy [--quick] [--data DIR] [--out DIR] "
                           "[freefall|bar|cantilever|restitution|incline|spot|jelly|frequency|stability|stress ...]\n");
      return 2;
    }
  }
  auto wanted = [&](const std::string& name) { return scenes.empty() || scenes.count(name) > 0; };
  const std::string out = options.csv;
  std::filesystem::create_directories(out);
  std::printf("bench_accuracy%s: %d hardware threads; CSVs in %s\n", gQuick ? " --quick" : "",
    int(std::thread::hardware_concurrency()), out.c_str());

  std::map<std::string, std::vector<Row>> byScene;
  std::vector<std::string> notes;
  auto runScene = [&](const LabScene& s) {
    std::printf("scene %s\n", s.name.c_str());
    std::vector<Row> rows = sweep(s);
    writeCsv(out + "/" + s.name + ".csv", rows);
    byScene[s.name] = rows;
  };
  if (wanted("freefall"))
  {
    const LabScene s = freeFallScene();
    runScene(s);
    for (const char* solver : { "Euler", "Euler-Cromer", "Implicit Euler", "Projective Dynamics" })
    {
      checkDecreasing(byScene["freefall"], "mass-spring", solver);
    }
    checkDecreasing(byScene["freefall"], "PBD", "Gauss-Seidel");
  }
  if (wanted("bar"))
  {
    const ElasticScene e = barScene();
    notes.push_back(e.summary);
    runScene(e.scene);
    for (const char* solver : { "Midpoint", "Verlet", "Euler-Cromer", "Implicit Euler" })
    {
      checkDecreasing(byScene["bar"], "mass-spring", solver);
    }
  }
  if (wanted("cantilever") && !gQuick)
  {
    const ElasticScene e = cantileverScene();
    notes.push_back(e.summary);
    runScene(e.scene);
  }
  if (wanted("restitution"))
  {
    notes.push_back("restitution: the particle sheet is PBD/XPBD only; the tet cube runs every method "
                    "(mass-spring through massspring/contact_response.h)");
    std::printf("  %s\n", notes.back().c_str());
    runScene(restitutionScene(false));
    runScene(restitutionScene(true));
  }
  if (wanted("incline"))
  {
    notes.push_back("incline: every method; the implicit integrators hold the floor in their solve and "
                    "apply Coulomb friction to the points it holds (stuck points fixed in the next solve)");
    runScene(inclineScene(30.0, 0.3, false));
    runScene(inclineScene(20.0, 0.5, true));
  }
  // Spot (a soft foam, E 1e4) lands 1 cm down at 45 ms. The demo's jelly (the filter's default
  // material) falls 0.30 m, lands at 0.25 s at 2.4 m/s and squashes: far larger deformation.
  const DropSpec spot{ "spot", "TetGen of keenan-spot/spot_triangulated.obj, scaled to a 0.2 m diagonal, 1 cm above "
                               "the floor", 0.1, { 1, 2 }, 1e4, 1e-5 };
  const DropSpec jelly{ "jelly", "data/jelly.vtu (the demo's), bottom 0.30 m above the floor", 0.4, { 32, 64 },
    MaterialSettings{}.physical.youngsModulus, MaterialSettings{}.physical.dampingTime };
  for (const DropSpec* d : { &spot, &jelly })
  {
    if (!wanted(d->name) || gQuick)
    {
      continue;
    }
    std::string note;
    TetMesh mesh = d == &spot
      ? publicSurfaceBody(options.dataDir + "/keenan-spot/spot_triangulated.obj", options.dataDir, 0.01, note)
      : demoJelly(std::string(SOFTBODY_PROJECT_DATA_DIR) + "/jelly.vtu", note);
    LabScene s;
    if (meshDropScene(*d, std::move(mesh), s, note))
    {
      runScene(s);
    }
    notes.push_back(note);
  }
  std::ofstream summary(out + "/summary.md");
  summary << "# Accuracy and stability lab" << (gQuick ? " (--quick)" : "") << "\n\n";
  for (const std::string& n : notes)
  {
    summary << "- " << n << "\n";
  }
  if (!byScene.empty())
  {
    const std::string fastest = fastestTable(byScene);
    const std::string substeps = substepTable(byScene);
    std::printf("\nFastest run per error target:\n%s\nSubsteps against iterations:\n%s", fastest.c_str(),
      substeps.c_str());
    summary << "\n## Fastest run per error target\n\n" << fastest << "\n## Substeps against iterations\n\n"
            << substeps;
  }
  if (!gModelAnswers.empty())
  {
    const std::string table = modelTable();
    std::printf("\nMaterial models against elasticity:\n%s", table.c_str());
    std::ofstream(out + "/models.md") << table;
    summary << "\n## Material models against elasticity\n\n" << table;
  }
  if (wanted("frequency"))
  {
    std::printf("frequency\n");
    const std::string table = bench::frequencyTable(options.dataDir, out, gQuick, fail);
    std::printf("%s", table.c_str());
    std::ofstream(out + "/frequency.md") << table;
    summary << "\n## Highest frequency: estimates against the converged value\n\n" << table;
  }
  if (wanted("stability"))
  {
    std::printf("stability\n");
    const std::string table = stabilityTable(options.dataDir, out);
    std::printf("%s", table.c_str());
    std::ofstream(out + "/stability.md") << table;
    summary << "\n## Largest stable step\n\n" << table;
  }
  if (wanted("stress"))
  {
    std::printf("stress\n");
    const std::string table = stressMatrix(out);
    std::printf("%s", table.c_str());
    std::ofstream(out + "/stress.md") << table;
    summary << "\n## Stress matrix\n\n" << table;
  }
  if (!gFailures.empty())
  {
    std::printf("\n%zu check(s) failed:\n", gFailures.size());
    for (const std::string& f : gFailures)
    {
      std::printf("  %s\n", f.c_str());
    }
    return 1;
  }
  std::printf("\nall checks passed\n");
  return 0;
}
