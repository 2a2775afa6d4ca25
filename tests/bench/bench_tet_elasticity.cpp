// The continuum models' element passes against the spring network's, per tet, on the same
// meshes and in the same run:
//   - forces: the explicit integrators' force pass (computeInternalForces for the network,
//     computeTetElasticForces for Corotated and Stable Neo-Hookean);
//   - Newton: one evaluation of the incremental potential plus the assembly of its
//     PSD-projected Hessian (what Implicit Euler does per Newton iteration);
//   - XPBD: one Gauss-Seidel iteration over the body's constraints (the network's edge links and
//     tet volumes, or each continuum tet's deviatoric and hydrostatic pair), 1 thread;
//   - the bandwidth bound of the continuum force pass: the bytes it must move per tet (points
//     read, shape gradients and constants read, corner forces written and gathered) over the
//     triad bandwidth measured here (memory_bandwidth.h), as a time per tet.
// Then Implicit Euler with Stable Neo-Hookean dropping the body onto the floor at 1/60 s steps:
// wall time per simulated second, Newton iterations per step (full run: the ~180k-tet TetGen
// ellipsoid; smoke: a small box). And the rotation-variant SVD every Corotated and Stable
// Neo-Hookean stress, Hessian and XPBD projection starts from: the closed form (with its
// JacobiSVD fallback) against JacobiSVD alone, on each mesh's deformation gradients at rest and
// in a rotated, stretched and jittered state (Jacobi's sweeps grow with how far F's singular
// directions are from the axes, so the rest state is its best case). Results also go to CSV.
//
// Usage: bench_tet_elasticity [--smoke] [--data <shared data dir>] [--csv <file>] [--mesh <spec>]
#include "bench_meshes.h"
#include "bench_options.h"
#include "memory_bandwidth.h"

#include "softbody/massspring/mass_spring_forces.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/massspring/model_potential_factory.h"
#include "softbody/material/isotropic_elasticity.h"
#include "softbody/material/mass.h"
#include "softbody/material/tet_elasticity.h"
#include "softbody/material/tet_elastic_forces.h"
#include "softbody/mesh/mesh_generators.h"
#include "softbody/mesh/topology.h"
#include "softbody/pbd/pbd_simulation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

using namespace softbody;

namespace
{

double secondsSince(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Best of `repeat` timings of `pass` [s].
template <class Pass>
double bestOf(int repeat, Pass&& pass)
{
  double best = 1e300;
  for (int k = 0; k < repeat; ++k)
  {
    const auto start = std::chrono::steady_clock::now();
    pass();
    best = std::min(best, secondsSince(start));
  }
  return best;
}

/// Bytes the continuum force pass must move per tet: 4 points (24 B each) and its shape
/// gradients (96 B) and constants (5 doubles) read, 4 corner forces (96 B) written and read again
/// by the gather, and per point one force written (about a fifth of a point per tet).
constexpr double kBytesPerTet = 4 * 24 + 96 + 40 + 2 * 96 + 0.2 * 24;

struct Row
{
  std::string mesh, model;
  std::size_t tets = 0;
  double forceNs = 0.0, newtonNs = 0.0, xpbdNs = 0.0;
};

/// Seconds of one XPBD Gauss-Seidel iteration of `model` on the mesh (best of `repeat` steps of
/// 10 iterations, the solve stages' own time).
double xpbdIterationSeconds(const TetMesh& mesh, MaterialModel model, int repeat)
{
  Body body;
  body.mesh.points = mesh.points;
  body.mesh.tets = mesh.tets;
  body.material.model = model; // E and nu: the material's defaults
  PbdSettings settings;
  settings.elasticFromMaterial = true;
  settings.collisions.mode = CollisionMode::Off;
  settings.reportConvergence = false;
  PbdSimulation sim(body, settings);
  const StepPlan& plan = sim.stepPlan();
  const auto solving = [&] {
    double seconds = 0.0;
    for (Stage stage : { Stage::SolveLinks, Stage::SolveTetElasticity, Stage::SolveVolumes })
    {
      seconds += plan.runs(stage) ? plan.seconds(stage) : 0.0;
    }
    return seconds;
  };
  sim.step(1.0 / 120.0); // warm-up
  double best = 1e300;
  for (int k = 0; k < repeat; ++k)
  {
    const double before = solving();
    sim.step(1.0 / 120.0);
    best = std::min(best, (solving() - before) / settings.iterations);
  }
  return best;
}

/// The mesh rotated 0.7 rad about an oblique axis, stretched by 1.2 / 0.9 / 1.0 along x / y / z
/// and each point moved by a deterministic jitter of up to 1 % of the body's size: gradients
/// whose singular directions are off the axes and differ from tet to tet, as in a real motion.
std::vector<Vec3> deformedPoints(const std::vector<Vec3>& rest)
{
  Vec3 lo = rest.front(), hi = rest.front();
  for (const Vec3& p : rest)
  {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double size = (hi - lo).maxCoeff();
  const Mat3 map = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix() *
    Vec3(1.2, 0.9, 1.0).asDiagonal();
  std::vector<Vec3> out(rest.size());
  for (std::size_t i = 0; i < rest.size(); ++i)
  {
    const double k = static_cast<double>(i);
    const Vec3 jitter(std::sin(12.9898 * k), std::sin(78.233 * k), std::sin(37.719 * k));
    out[i] = map * rest[i] + 0.01 * size * jitter;
  }
  return out;
}

struct SvdRow
{
  std::string mesh, state;
  double closedNs = 0.0, jacobiNs = 0.0, fallbackShare = 0.0;
};

/// Times the rotation-variant SVD of every tet's F at `x`, closed form against JacobiSVD.
SvdRow timeSvds(const std::string& mesh, const std::string& state, const Topology& topology,
  const TetElasticConstants& constants, const std::vector<Vec3>& x, int repeat)
{
  std::vector<Mat3> gradients(topology.tets.size());
  for (std::size_t t = 0; t < gradients.size(); ++t)
  {
    gradients[t] = deformationGradient(topology, constants, t, x);
  }
  double sink = 0.0; // keeps the compiler from dropping the SVDs
  const double closed = bestOf(repeat, [&] {
    for (const Mat3& f : gradients)
    {
      sink += rotationVariantSvd(f).s(2);
    }
  });
  const double jacobi = bestOf(repeat, [&] {
    for (const Mat3& f : gradients)
    {
      sink += rotationVariantSvdJacobi(f).s(2);
    }
  });
  std::size_t fallbacks = 0;
  for (const Mat3& f : gradients)
  {
    RotationVariantSvd svd;
    fallbacks += rotationVariantSvdClosedForm(f, svd) ? 0 : 1;
  }
  if (!std::isfinite(sink))
  {
    std::printf("(non-finite singular values on %s)\n", mesh.c_str());
  }
  const double perTet = 1e9 / static_cast<double>(gradients.size());
  return { mesh, state, closed * perTet, jacobi * perTet,
    static_cast<double>(fallbacks) / static_cast<double>(gradients.size()) };
}

MaterialSettings materialOf(MaterialModel model, VolumetricFormulation volumetric = VolumetricFormulation::PerTet)
{
  MaterialSettings material;
  material.model = model;
  material.volumetric = volumetric;
  return material;
}

/// The rows of the cost table: each model, and the continuum ones again with the nodal-averaged
/// volume term (its extra passes over points and tets, and the Hessian's coupling).
struct Variant
{
  MaterialModel model;
  VolumetricFormulation volumetric;
};
constexpr Variant kVariants[] = {
  { MaterialModel::SpringNetwork, VolumetricFormulation::PerTet },
  { MaterialModel::Corotated, VolumetricFormulation::PerTet },
  { MaterialModel::StableNeoHookean, VolumetricFormulation::PerTet },
  { MaterialModel::Corotated, VolumetricFormulation::NodalAverage },
  { MaterialModel::StableNeoHookean, VolumetricFormulation::NodalAverage },
};

std::string variantName(const Variant& variant)
{
  return std::string(materialModelName(variant.model))
    + (variant.volumetric == VolumetricFormulation::NodalAverage ? " (Nodal Average)" : "");
}

/// A cost and its ratio to the network's as table cells; XPBD refuses the nodal average (NaN).
std::string costCells(double ns, double base)
{
  if (!std::isfinite(ns))
  {
    return "refused | -";
  }
  char cells[64];
  std::snprintf(cells, sizeof cells, "%.1f | %.2f", ns, ns / base);
  return cells;
}

} // namespace

int main(int argc, char** argv)
{
  const bench::Options options =
    bench::parseOptions(argc, argv, "bench_tet_elasticity", "bench_tet_elasticity.csv");
  const double bandwidth = bench::measureTriadBandwidth(std::size_t(1) << 24, options.smoke ? 2 : 5);
  std::printf("triad bandwidth %.2f GB/s\n", bandwidth * 1e-9);
  std::vector<Row> rows;
  std::vector<SvdRow> svdRows;
  std::vector<bench::NamedMesh> meshes = bench::benchmarkMeshes(options.smoke, options.dataDir, options.mesh);
  std::printf("%-22s %8s  %-34s %10s %8s %12s %8s %10s %8s\n", "mesh", "tets", "model", "force ns/t",
    "x net", "Newton ns/t", "x net", "XPBD ns/t", "x net");
  for (bench::NamedMesh& named : meshes)
  {
    std::vector<std::string> warnings;
    TetMesh mesh = prepareTetMesh(named.mesh, InvertedTetPolicy::Reorient, warnings);
    const Topology topology = buildTopology(mesh.points.size(), mesh.tets);
    const std::size_t tets = topology.tets.size();
    const int repeat = options.smoke ? 2 : 5;
    const std::vector<Vec3> x = mesh.points;
    const std::vector<Vec3> v(x.size(), Vec3(0.01, 0.0, -0.02));
    std::vector<Vec3> out, gradient;
    double networkForce = 0.0, networkNewton = 0.0, networkXpbd = 0.0;
    for (const Variant& variant : kVariants)
    {
      const MaterialModel model = variant.model;
      const MaterialSettings material = materialOf(model, variant.volumetric);
      const ElementConstants network = computeElementConstants(topology, mesh.points, material, warnings);
      TetElasticConstants continuum;
      if (isContinuum(model))
      {
        continuum = computeTetElasticConstants(topology, mesh.points, material, warnings);
      }
      double volume = 0.0;
      for (double v0 : network.restVolume)
      {
        volume += v0;
      }
      const PointMasses masses = distributeMass(topology, network.restVolume,
        totalMassOf(material, volume), material.massDistribution, 0.0, {});
      ForceScratch networkScratch;
      TetElasticScratch tetScratch;
      const double force = bestOf(repeat, [&] {
        if (isContinuum(model))
        {
          computeTetElasticForces(topology, continuum, x, v, tetScratch, out);
        }
        else
        {
          computeInternalForces(topology, network, x, v, networkScratch, out);
        }
      });
      auto potential = makeIncrementalPotential(topology,
        BodyElements{ model, &network, isContinuum(model) ? &continuum : nullptr }, masses,
        Vec3(0, 0, -9.81));
      BlockSparseMatrix hessian(topology);
      potential->beginStep(x, v, 1.0 / 60);
      const double newton = bestOf(repeat, [&] {
        potential->evaluate(x, gradient);
        potential->assembleHessian(x, hessian);
      });
      // XPBD projects tet by tet and refuses the point-coupled volume term (pbd_setup.cpp).
      const double xpbd = variant.volumetric == VolumetricFormulation::PerTet
        ? xpbdIterationSeconds(mesh, model, std::min(repeat, 3))
        : std::nan("");
      const double perTet = 1e9 / static_cast<double>(tets);
      Row row{ named.name, variantName(variant), tets, force * perTet, newton * perTet, xpbd * perTet };
      if (!isContinuum(model))
      {
        networkForce = row.forceNs;
        networkNewton = row.newtonNs;
        networkXpbd = row.xpbdNs;
      }
      std::printf("%-22s %8zu  %-34s %10.1f %8.2f %12.1f %8.2f %10.1f %8.2f\n", row.mesh.c_str(), tets,
        row.model.c_str(), row.forceNs, row.forceNs / networkForce, row.newtonNs,
        row.newtonNs / networkNewton, row.xpbdNs, row.xpbdNs / networkXpbd);
      rows.push_back(row);
    }
    const TetElasticConstants svdConstants =
      computeTetElasticConstants(topology, mesh.points, materialOf(MaterialModel::Corotated), warnings);
    svdRows.push_back(timeSvds(named.name, "rest", topology, svdConstants, x, repeat));
    svdRows.push_back(timeSvds(named.name, "deformed", topology, svdConstants, deformedPoints(x), repeat));
    const double bytes = kBytesPerTet;
    std::printf("%-22s %8zu  %-34s %10.1f   (bandwidth bound of the continuum force pass)\n",
      named.name.c_str(), tets, "bound", 1e9 * bytes / bandwidth);
  }

  std::printf("\n%-22s %-9s %14s %14s %10s %12s\n", "mesh", "state", "closed ns/t", "Jacobi ns/t",
    "x Jacobi", "fallbacks");
  for (const SvdRow& row : svdRows)
  {
    std::printf("%-22s %-9s %14.1f %14.1f %10.2f %11.2f%%\n", row.mesh.c_str(), row.state.c_str(),
      row.closedNs, row.jacobiNs, row.jacobiNs / row.closedNs, 100.0 * row.fallbackShare);
  }

  // Implicit Euler with Stable Neo-Hookean: a body dropped a centimetre onto the floor.
  const bench::NamedMesh landing = options.smoke
    ? bench::NamedMesh{ "box_1536", makeTetBox(8, 8, 4, 0.02) }
    : bench::meshFromSpec(options.mesh.empty() ? "ellipsoid180k" : options.mesh, options.dataDir);
  Body body;
  body.mesh = landing.mesh;
  body.material.model = MaterialModel::StableNeoHookean;
  body.material.massDistribution = MassDistribution::LumpedVolume;
  double lowest = 1e300;
  for (const Vec3& p : body.mesh.points)
  {
    lowest = std::min(lowest, p.z());
  }
  SceneSettings scene;
  scene.integrator = Integrator::ImplicitEuler;
  scene.timeStep = 1.0 / 60;
  scene.floorEnabled = true;
  scene.floor.origin = Vec3(0, 0, lowest - 0.01);
  MassSpringSimulation sim(body, scene);
  const double simulated = options.smoke ? 0.1 : 0.5;
  const auto start = std::chrono::steady_clock::now();
  sim.advance(simulated);
  const double wall = secondsSince(start);
  const ImplicitConvergence& c = *sim.implicitConvergence();
  std::vector<double> ratios = sim.tetVolumeRatios();
  const auto inverted = std::count_if(ratios.begin(), ratios.end(), [](double r) { return r <= 0.0; });
  std::printf("Implicit Euler, Stable Neo-Hookean, %s (%zu tets) at 1/60 s: %.2f s per simulated "
              "second, %.1f Newton iterations per step, %.0f CG iterations per Newton iteration, "
              "%llu unconverged steps, %td inverted tets\n",
    landing.name.c_str(), landing.mesh.tets.size(), wall / simulated,
    double(c.iterationsTotal) / double(c.steps),
    double(c.linearIterationsTotal) / std::max(1.0, double(c.iterationsTotal)), c.unconvergedSteps,
    inverted);

  std::ofstream csv(options.csv);
  csv << "mesh,tets,model,force_ns_per_tet,newton_ns_per_tet,xpbd_iteration_ns_per_tet\n";
  for (const Row& row : rows)
  {
    csv << row.mesh << ',' << row.tets << ',' << row.model << ',' << row.forceNs << ','
        << row.newtonNs << ',' << row.xpbdNs << '\n';
  }
  csv << "# bandwidth_GBps," << bandwidth * 1e-9 << "\n";
  for (const SvdRow& row : svdRows)
  {
    csv << "# svd," << row.mesh << ',' << row.state << ',' << row.closedNs << ',' << row.jacobiNs << ','
        << row.fallbackShare << '\n';
  }
  csv << "# implicit_snh," << landing.name << ',' << landing.mesh.tets.size() << ','
      << wall / simulated << ',' << double(c.iterationsTotal) / double(c.steps) << '\n';

  // The same as a table for docs/performance.md (scripts/update_docs_tables.py), beside the CSV.
  const std::string md = bench::tableBeside(options.csv);
  std::ofstream table(md);
  table << "| mesh | tets | material model | forces [ns/tet] | x network | Newton pass [ns/tet] | x network "
           "| XPBD iteration [ns/tet] | x network |\n"
           "|---|---|---|---|---|---|---|---|---|\n";
  double forceBase = 1.0, newtonBase = 1.0, xpbdBase = 1.0;
  char line[256];
  for (const Row& row : rows)
  {
    if (row.model == materialModelName(MaterialModel::SpringNetwork))
    {
      forceBase = row.forceNs;
      newtonBase = row.newtonNs;
      xpbdBase = row.xpbdNs;
    }
    std::snprintf(line, sizeof line, "| %s | %zu | %s | %.1f | %.2f | %.1f | %.2f | %s |\n",
      row.mesh.c_str(), row.tets, row.model.c_str(), row.forceNs, row.forceNs / forceBase, row.newtonNs,
      row.newtonNs / newtonBase, costCells(row.xpbdNs, xpbdBase).c_str());
    table << line;
  }
  table << "\n## Bound and landing\n\n| triad bandwidth [GB/s] | force-pass bound [ns/tet] | landing mesh "
           "| tets | s per simulated second | Newton iterations per step | CG iterations per Newton iteration "
           "|\n|---|---|---|---|---|---|---|\n";
  std::snprintf(line, sizeof line, "| %.2f | %.1f | %s | %zu | %.2f | %.1f | %.0f |\n", bandwidth * 1e-9,
    1e9 * kBytesPerTet / bandwidth, landing.name.c_str(), landing.mesh.tets.size(), wall / simulated,
    double(c.iterationsTotal) / double(c.steps),
    double(c.linearIterationsTotal) / std::max(1.0, double(c.iterationsTotal)));
  table << line;
  table << "\n## Rotation-variant SVD\n\nPer tet, the closed form (with its JacobiSVD fallback) against "
           "JacobiSVD alone:\n\n| mesh | state | closed form [ns/tet] | JacobiSVD [ns/tet] | x closed form "
           "| fallbacks |\n|---|---|---|---|---|---|\n";
  for (const SvdRow& row : svdRows)
  {
    std::snprintf(line, sizeof line, "| %s | %s | %.1f | %.1f | %.2f | %.2f %% |\n", row.mesh.c_str(),
      row.state.c_str(), row.closedNs, row.jacobiNs, row.jacobiNs / row.closedNs, 100.0 * row.fallbackShare);
    table << line;
  }
  return 0;
}
