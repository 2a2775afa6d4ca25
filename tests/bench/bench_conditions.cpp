// What loads and boundary conditions cost per step, in the same run and on the same meshes,
// against the body pinned the old way (PinnedPointsArray, its lowest tenth of points): the same
// support as a Fixed condition (the same physics: the states must be equal, and the bench says
// whether they are to the bit), with a force spread by mass over the top tenth, and with a
// pressure on the whole surface (a follower load: the boundary faces' area vectors every
// evaluation). Euler-Cromer (per force evaluation) and Implicit Euler (per step; Newton sees the
// loads in its potential, and its iterations per step are printed, since a load changes them),
// Corotated. Ratios printed; CSV and a Markdown table beside it.
//
// Usage: bench_conditions [--smoke] [--data <shared data dir>] [--csv <file>] [--mesh <spec>]
#include "bench_meshes.h"
#include "bench_options.h"

#include "softbody/common/errors.h"

#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>

using namespace softbody;

namespace
{

struct Row
{
  std::string mesh, integrator, conditions;
  std::size_t tets = 0;
  double msPerStep = 0.0, ratio = 1.0;
  double newtonPerStep = 0.0; ///< Implicit Euler's iterations per step (0 for explicit)
};

/// The points whose z is in the lowest (or highest) `fraction` of the body's height.
std::vector<std::int32_t> slab(const std::vector<Vec3>& points, double fraction, bool top)
{
  double low = 1e300, high = -1e300;
  for (const Vec3& p : points)
  {
    low = std::min(low, p.z());
    high = std::max(high, p.z());
  }
  std::vector<std::int32_t> set;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const double z = points[i].z();
    if (top ? z >= high - fraction * (high - low) : z <= low + fraction * (high - low))
    {
      set.push_back(static_cast<std::int32_t>(i));
    }
  }
  return set;
}

std::vector<Condition> conditionsOf(const std::string& which, const std::vector<Vec3>& points)
{
  if (which == "pinned array")
  {
    return {};
  }
  Condition support;
  support.name = "support";
  support.points = slab(points, 0.1, false);
  std::vector<Condition> out{ support };
  if (which == "support + force")
  {
    Condition force;
    force.name = "force";
    force.kind = ConditionKind::Force;
    force.spread = ForceSpread::ByMass;
    force.force = Vec3(1.0, 0.0, 0.0);
    force.points = slab(points, 0.1, true);
    out.push_back(force);
  }
  else if (which == "support + pressure") // on every point: the whole surface
  {
    Condition gas;
    gas.name = "gas";
    gas.kind = ConditionKind::Pressure;
    gas.pressure = 100.0;
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      gas.points.push_back(static_cast<std::int32_t>(i));
    }
    out.push_back(gas);
  }
  return out;
}

} // namespace

int main(int argc, char** argv)
{
  const bench::Options options =
    bench::parseOptions(argc, argv, "bench_conditions", "bench_conditions.csv");
  std::vector<bench::NamedMesh> meshes = bench::benchmarkMeshes(options.smoke, options.dataDir, options.mesh);
  std::vector<Row> rows;
  std::printf("%-22s %8s  %-15s %-18s %10s %8s %8s\n", "mesh", "tets", "integrator", "conditions",
    "ms/step", "x pinned", "Newton");
  for (const bench::NamedMesh& named : meshes)
  {
    for (Integrator integrator : { Integrator::EulerCromer, Integrator::ImplicitEuler })
    {
      const bool implicit = isImplicit(integrator);
      double base = 0.0;
      std::vector<Vec3> pinnedState;
      for (const std::string which :
        { "pinned array", "Fixed condition", "support + force", "support + pressure" })
      {
        Body body;
        body.mesh = named.mesh;
        body.material.model = MaterialModel::Corotated;
        body.conditions = conditionsOf(which, body.mesh.points);
        if (which == "pinned array")
        {
          body.pinned.assign(body.mesh.points.size(), 0);
          for (std::int32_t p : slab(body.mesh.points, 0.1, false))
          {
            body.pinned[static_cast<std::size_t>(p)] = 1;
          }
        }
        SceneSettings scene;
        scene.integrator = integrator;
        scene.collisions.mode = CollisionMode::Off;
        MassSpringSimulation sim(body, scene);
        // A fixed step for all three, so each is timed over the same steps.
        const double h = implicit ? 1.0 / 60 : sim.estimatedStableStep() * 0.9;
        const int steps = implicit ? (options.smoke ? 2 : 6) : (options.smoke ? 20 : 200);
        scene.timeStep = h;
        MassSpringSimulation timed(body, scene);
        const auto start = std::chrono::steady_clock::now();
        try
        {
          timed.advance(steps * h);
        }
        catch (const SimulationDivergedError& error)
        {
          // A finding about the scene's step (reported in the row), not about the conditions'
          // cost: the other cases and meshes are still measured.
          std::printf("%-22s %8zu  %-15s %-18s blew up: %s\n", named.name.c_str(), named.mesh.tets.size(),
            integratorName(integrator), which.c_str(), error.what());
          rows.push_back(Row{ named.name, integratorName(integrator), which + " (" + bench::blowUpCause(error.what(), "blew up at 0.9 x the estimated stable step") + ")",
            named.mesh.tets.size(), 0.0 });
          continue;
        }
        const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        Row row{ named.name, integratorName(integrator), which, named.mesh.tets.size(),
          1e3 * seconds / static_cast<double>(timed.stepCount()) };
        base = which == std::string("pinned array") ? row.msPerStep : base;
        row.ratio = base > 0.0 ? row.msPerStep / base : 0.0;
        if (const ImplicitConvergence* c = timed.implicitConvergence())
        {
          row.newtonPerStep = double(c->iterationsTotal) / double(std::max<unsigned long long>(1, c->steps));
        }
        std::printf("%-22s %8zu  %-15s %-18s %10.3f %8.2f %8.1f", row.mesh.c_str(), row.tets,
          row.integrator.c_str(), row.conditions.c_str(), row.msPerStep, row.ratio, row.newtonPerStep);
        if (which == std::string("pinned array"))
        {
          pinnedState = timed.positions();
        }
        else if (which == std::string("Fixed condition"))
        {
          std::printf("   states %s", timed.positions() == pinnedState ? "equal to the bit" : "DIFFER");
        }
        std::printf("\n");
        rows.push_back(row);
      }
    }
  }

  std::ofstream csv(options.csv);
  csv << "mesh,tets,integrator,conditions,ms_per_step,ratio_to_pinned,newton_per_step\n";
  for (const Row& row : rows)
  {
    csv << row.mesh << ',' << row.tets << ',' << row.integrator << ',' << row.conditions << ','
        << row.msPerStep << ',' << row.ratio << ',' << row.newtonPerStep << '\n';
  }
  // The same as a table for docs/performance.md (scripts/update_docs_tables.py), beside the CSV.
  const std::string md = bench::tableBeside(options.csv);
  std::ofstream table(md);
  table << "| mesh | tets | integrator | conditions | ms per step | x pinned array | Newton iterations per step |\n"
           "|---|---|---|---|---|---|---|\n";
  char line[256];
  for (const Row& row : rows)
  {
    if (row.msPerStep == 0.0) // blew up: nothing was timed
    {
      std::snprintf(line, sizeof line, "| %s | %zu | %s | %s | - | - | - |\n", row.mesh.c_str(), row.tets,
        row.integrator.c_str(), row.conditions.c_str());
    }
    else
    {
      std::snprintf(line, sizeof line, "| %s | %zu | %s | %s | %.3f | %.2f | %.1f |\n", row.mesh.c_str(),
        row.tets, row.integrator.c_str(), row.conditions.c_str(), row.msPerStep, row.ratio, row.newtonPerStep);
    }
    table << line;
  }
  return 0;
}
