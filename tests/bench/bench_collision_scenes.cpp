// Collision scenes through the whole PBD/XPBD step, timed by the step
// plan's own stage timers, so each frame's time splits into collision detection (broad +
// narrow phase, once per substep), the contact solve (the inequality projections inside the
// iterations) and everything else (prediction, links, volumes, velocity update, restitution):
//
// 1. Pile: 8 voxelized bodies (particle lattices with 26-neighbour links, spheres and boxes),
//    dropped in two layers onto a ramp obstacle tilted 25 degrees above the floor;
//    Collisions = Obstacles + Bodies.
// 2. Cloth: a square sheet dropped onto a sphere obstacle standing on the floor; it drapes
//    and its free sides fold onto it and onto themselves; Collisions = Obstacles + Bodies +
//    Self.
// 4. Ten tori (tenToriScene): stacked into a pile, against the same bodies apart.
// 3. Tori: two TetGen tori (~3,000 points each, data/torus.vtp's shape) on the floor, the upper
//    one placed 0.25 m into the lower one (an overlapping start), against the same
//    pair placed 1 mm apart, which lands on each other; XPBD defaults, 0.05 s frames,
//    Collisions = Obstacles + Bodies. The overlapping pair must cost about what the touching
//    pair costs (the detection's candidates per point are bounded); the ratio is printed.
//
// Each scene runs with collisions at 1 and all threads, and with Collisions Off (the bodies
// fall freely: the cost of everything else) at all threads; the scenes with body surfaces
// (cloth, tori) also without edge-edge contacts (CollisionSettings::edgeContacts), which is
// what those cost. The ratios are measured in the same run, and a hash of the final positions
// shows the thread counts computed the same thing. The table goes beside the CSV as .md, for
// docs/performance.md (scripts/bench.sh).
// The load average is printed first: on a shared machine other processes' work shows in every
// time.
//
// Usage: bench_collision_scenes [--smoke] [--csv PATH] [--repeat N]
#include "bench_options.h"
#include "unit/pbd_collision_scenes.h"
#include "unit/torus_pair.h"

#include "softbody/lattice/lattice.h"
#include "softbody/pbd/cloth.h"
#include "softbody/pbd/pbd_simulation.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <string>
#include <tuple>
#include <vector>

using namespace softbody;

namespace
{

struct CollisionScene
{
  std::string name;
  Body body;
  PbdSettings settings;
  std::vector<ObstacleSurface> obstacles;
  double frame = 1.0 / 30.0; ///< [s]
  int frames = 30;
};

/// A voxelized body: the lattice nodes of spacing h inside `inside`, linked to their 26
/// neighbours, centred at `centre`, of total mass `mass`.
Body voxelBody(double h, double halfWidth, const Vec3& centre, double mass,
  const std::function<bool(const Vec3&)>& inside)
{
  LatticeGrid grid;
  const int n = static_cast<int>(std::ceil(2.0 * halfWidth / h)) + 1;
  grid.origin = Vec3::Constant(-halfWidth);
  grid.spacing = h;
  grid.nodes = { n, n, n };
  std::vector<char> flags(grid.nodeCount());
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        flags[grid.nodeIndex(i, j, k)] = inside(grid.position(i, j, k));
  const Lattice lattice = buildLattice(grid, flags);
  Body body;
  for (const Vec3& p : lattice.points)
  {
    body.mesh.points.push_back(centre + p);
  }
  body.links = lattice.links;
  body.pointMass.assign(body.mesh.points.size(), mass / static_cast<double>(body.mesh.points.size()));
  return body;
}

CollisionScene pileScene(bool smoke)
{
  CollisionScene scene;
  scene.name = "pile";
  const double r = 0.1, h = smoke ? 0.04 : 0.02; // bodies 0.2 m across
  for (int b = 0; b < 8; ++b)
  {
    const Vec3 centre(-0.15 + 0.3 * (b % 2), -0.15 + 0.3 * ((b / 2) % 2), 0.75 + 0.3 * (b / 4));
    const bool ball = (b + b / 2 + b / 4) % 2 == 0;
    test::appendBody(scene.body, voxelBody(h, r, centre, 1.0, [&](const Vec3& p) {
      return ball ? p.norm() <= r : p.cwiseAbs().maxCoeff() <= 0.8 * r;
    }));
  }
  PbdSettings& s = scene.settings;
  s.formulation = PbdFormulation::Pbd;
  s.particleRadius = 0.5 * h;
  s.floorEnabled = true;
  s.collisions.mode = CollisionMode::ObstaclesAndBodies;
  // mu = 0.6 > tan 25 deg: the bodies stick to the ramp and pile up there.
  s.collisions.staticFriction = s.collisions.dynamicFriction = 0.6;
  const double a = 25.0 * M_PI / 180.0;
  scene.obstacles = { test::quadObstacle(Vec3(0.0, 0.0, 0.35), Vec3(std::cos(a), 0.0, -std::sin(a)), Vec3(0.0, 0.8, 0.0)) };
  scene.frames = smoke ? 15 : 45;
  return scene;
}

CollisionScene clothScene(bool smoke)
{
  CollisionScene scene;
  scene.name = "cloth";
  ClothSpec spec;
  spec.particlesAlong1 = spec.particlesAlong2 = smoke ? 16 : 48;
  spec.origin = Vec3(-0.6, -0.6, 0.5);
  spec.point1 = Vec3(0.6, -0.6, 0.5);
  spec.point2 = Vec3(-0.6, 0.6, 0.5);
  spec.diagonalStiffness = 0.2;
  scene.body = makeCloth(spec);
  PbdSettings& s = scene.settings;
  s.formulation = PbdFormulation::Pbd;
  s.substeps = 2;
  s.floorEnabled = true;
  s.collisions.mode = CollisionMode::ObstaclesBodiesAndSelf;
  s.collisions.staticFriction = s.collisions.dynamicFriction = 0.3;
  scene.obstacles = { test::sphereObstacle(Vec3(0.0, 0.0, 0.2), 0.2) };
  scene.frames = smoke ? 15 : 45;
  return scene;
}

/// Two tori, the upper one `overlap` metres into the lower one (< 0: a gap).
CollisionScene torusScene(const std::string& name, double overlap, bool smoke)
{
  CollisionScene scene;
  scene.name = name;
  scene.body = test::torusPair(overlap, smoke ? 2e-4 : 2e-5).body;
  PbdSettings& s = scene.settings; // XPBD defaults
  s.floorEnabled = true;
  s.collisions.mode = CollisionMode::ObstaclesAndBodies;
  scene.frame = 0.05;
  scene.frames = smoke ? 4 : 12; // 0.6 s: the lower torus lands at ~0.25 s, the upper on it
  return scene;
}

/// Ten TetGen tori (data/torus.vtp's shape, 8,205 tets each, 2,349 points) dropped onto the floor, stacked
/// 1 mm apart (`tori10-pile`: each lands on the one below) or side by side 0.6 m apart
/// (`tori10-apart`: each lands on the floor alone); XPBD defaults, 0.05 s frames. The pile over
/// the bodies apart is what resting on each other costs.
CollisionScene tenToriScene(bool pile, bool smoke)
{
  CollisionScene scene;
  scene.name = pile ? "tori10-pile" : "tori10-apart";
  const TetMesh torus = test::tetTorus(smoke ? 2e-4 : 1e-5);
  double low = 1e9, high = -1e9;
  for (const Vec3& p : torus.points)
  {
    low = std::min(low, p.z());
    high = std::max(high, p.z());
  }
  for (int k = 0; k < 10; ++k)
  {
    const Vec3 centre = pile ? Vec3(0.0, 0.0, 0.5 + k * (high - low + 0.001))
                             : Vec3(0.6 * (k % 5), 0.6 * (k / 5), 0.5);
    Body body;
    for (const Vec3& p : torus.points)
    {
      body.mesh.points.push_back(p + centre);
    }
    body.mesh.tets = torus.tets;
    test::appendBody(scene.body, body);
  }
  PbdSettings& s = scene.settings; // XPBD defaults
  s.floorEnabled = true;
  s.collisions.mode = CollisionMode::ObstaclesAndBodies;
  scene.frame = 0.05;
  scene.frames = smoke ? 4 : 12; // the lowest lands at ~0.25 s, the pile settles on it
  return scene;
}

struct Run
{
  double frameMs = 0.0;   ///< wall time per frame [ms]
  double detectMs = 0.0;  ///< of which collision detection
  double contactMs = 0.0; ///< and the contact solve
  std::size_t points = 0;
  std::uint64_t hash = 0;
  double lowest = 0.0;    ///< lowest point at the end [m] (sanity: on the floor, not below)
  double examinedPerPoint = 0.0; ///< narrow-phase pairs per colliding point, mean over the frames' last detections
  std::size_t mostExamined = 0;  ///< the most of one point in those detections
  std::size_t mostContacts = 0;
  double edgeContacts = 0.0;     ///< edge-edge contacts, mean over the frames' last detections
};

/// What a run collides: everything, nothing, or everything but edge against edge.
enum class Collide
{
  On,
  Off,
  WithoutEdges
};

const char* collideName(Collide c)
{
  return c == Collide::On ? "on" : (c == Collide::Off ? "off" : "no edges");
}

Run runScene(const CollisionScene& scene, int threads, Collide collide)
{
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  PbdSettings settings = scene.settings;
  if (collide == Collide::Off)
  {
    settings.collisions.mode = CollisionMode::Off;
  }
  settings.collisions.edgeContacts = collide != Collide::WithoutEdges;
  PbdSimulation sim(scene.body, settings);
  sim.setObstacles(scene.obstacles, 0.0);
  Run run;
  double examined = 0.0;
  const auto started = std::chrono::steady_clock::now();
  for (int f = 1; f <= scene.frames; ++f)
  {
    sim.advance(f * scene.frame);
    if (const CollisionDetector* detector = sim.collisionDetector())
    {
      const DetectionStats& stats = detector->stats();
      examined += static_cast<double>(stats.candidatePairs) / static_cast<double>(sim.positions().size());
      run.mostExamined = std::max(run.mostExamined, stats.mostExaminedPerPoint);
      run.mostContacts = std::max(run.mostContacts, stats.mostContactsPerPoint);
      run.edgeContacts += static_cast<double>(stats.edgeContacts) / scene.frames;
    }
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  run.examinedPerPoint = examined / scene.frames;
  const StepPlan& plan = sim.stepPlan();
  const double perFrame = 1e3 / scene.frames;
  run.frameMs = wall * perFrame;
  run.detectMs = plan.runs(Stage::CollisionDetect) ? plan.seconds(Stage::CollisionDetect) * perFrame : 0.0;
  run.contactMs = plan.runs(Stage::SolveContacts) ? plan.seconds(Stage::SolveContacts) * perFrame : 0.0;
  run.points = sim.positions().size();
  run.hash = bench::hashPositions(sim.positions());
  run.lowest = 1e9;
  for (const Vec3& p : sim.positions())
  {
    run.lowest = std::min(run.lowest, p.z());
  }
  return run;
}

std::string twoDecimals(double value)
{
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", value);
  return text;
}

/// The run with the least frame time of `repeat` (other processes share the machine).
Run best(const CollisionScene& scene, int threads, Collide collide, int repeat)
{
  Run fastest = runScene(scene, threads, collide);
  for (int k = 1; k < repeat; ++k)
  {
    const Run run = runScene(scene, threads, collide);
    fastest = run.frameMs < fastest.frameMs ? run : fastest;
  }
  return fastest;
}

} // namespace

int main(int argc, char** argv)
{
  const bench::Options options = bench::parseOptions(argc, argv, "bench_collision_scenes", "bench_collision_scenes.csv");
  const int maxThreads = std::max(1, tbb::info::default_concurrency());
  const int repeat = options.smoke ? 1 : options.repeat;
  double load[3] = { 0, 0, 0 };
  if (std::FILE* f = std::fopen("/proc/loadavg", "r"))
  {
    if (std::fscanf(f, "%lf %lf %lf", &load[0], &load[1], &load[2]) != 3)
    {
      load[0] = load[1] = load[2] = -1.0;
    }
    std::fclose(f);
  }
  std::printf("Collision scenes, PBD: ms per frame (wall), best of %d; %d threads available; load "
              "average %.2f %.2f %.2f%s\n",
    repeat, maxThreads, load[0], load[1], load[2], load[0] > 0.5 * maxThreads ? " (machine shared: times inflated)" : "");
  std::ofstream csv(options.csv);
  csv << "scene,points,threads,collisions,frame_ms,detect_ms,contact_solve_ms,edge_contacts,hash\n";
  // The same as a table for docs/performance.md (scripts/update_docs_tables.py), beside the CSV.
  const std::string md = bench::tableBeside(options.csv);
  std::ofstream table(md);
  table << "| scene | points | tets | threads | collisions | ms per frame | detection ms | contact solve ms | "
           "x Collisions Off | edge contacts | same state at 1 and " << maxThreads << " threads |\n"
           "|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::printf("%-12s %7s %7s %-10s %10s %10s %10s %10s %18s %9s %9s %9s %9s %9s\n", "scene", "points", "threads", "collisions",
    "frame ms", "detect ms", "contact ms", "other ms", "state hash", "lowest z", "pairs/pt", "most/pt", "contacts", "edge c.");
  int status = 0;
  char line[320];
  double toriFrameMs[2] = { 0.0, 0.0 }; // overlapping, touching (all threads)
  double toriDetectMs[2] = { 0.0, 0.0 };
  double tenToriFrameMs[2] = { 0.0, 0.0 }; // pile, apart (all threads)
  double tenToriDetectMs[2] = { 0.0, 0.0 };
  for (const CollisionScene& scene : { pileScene(options.smoke), clothScene(options.smoke),
         torusScene("tori-overlap", 0.25, options.smoke), torusScene("tori-touch", -0.001, options.smoke),
         tenToriScene(true, options.smoke), tenToriScene(false, options.smoke) })
  {
    const bool hasSurfaces = scene.name != "pile"; // the pile's bodies are particle lattices
    const Run one = best(scene, 1, Collide::On, repeat);
    const Run all = best(scene, maxThreads, Collide::On, repeat);
    const Run off = best(scene, maxThreads, Collide::Off, repeat);
    std::vector<std::tuple<int, Collide, Run>> runs{ { 1, Collide::On, one }, { maxThreads, Collide::On, all },
      { maxThreads, Collide::Off, off } };
    if (hasSurfaces)
    {
      runs.emplace_back(maxThreads, Collide::WithoutEdges, best(scene, maxThreads, Collide::WithoutEdges, repeat));
    }
    for (const auto& [threads, collide, run] : runs)
    {
      std::printf("%-12s %7zu %7d %-10s %10.2f %10.2f %10.2f %10.2f %18llx %9.4f %9.1f %9zu %9zu %9.1f\n", scene.name.c_str(),
        run.points, threads, collideName(collide), run.frameMs, run.detectMs, run.contactMs,
        run.frameMs - run.detectMs - run.contactMs, static_cast<unsigned long long>(run.hash), run.lowest,
        run.examinedPerPoint, run.mostExamined, run.mostContacts, run.edgeContacts);
      csv << scene.name << ',' << run.points << ',' << threads << ',' << collideName(collide) << ',' << run.frameMs
          << ',' << run.detectMs << ',' << run.contactMs << ',' << run.edgeContacts << ',' << run.hash << '\n';
      std::snprintf(line, sizeof line, "| %s | %zu | %zu | %d | %s | %.2f | %s | %s | %.2f | %.0f | %s |\n", scene.name.c_str(),
        run.points, scene.body.mesh.tets.size(), threads, collideName(collide), run.frameMs,
        collide == Collide::Off ? "-" : twoDecimals(run.detectMs).c_str(),
        collide == Collide::Off ? "-" : twoDecimals(run.contactMs).c_str(), run.frameMs / off.frameMs,
        run.edgeContacts, threads == 1 ? (one.hash == all.hash ? "yes" : "NO") : "");
      table << line;
    }
    if (hasSurfaces)
    {
      const Run& withoutEdges = std::get<2>(runs.back());
      std::printf("%-12s edge contacts on / off: %.2f x the frame time, %.2f x the detection time (%.0f edge contacts per frame)\n",
        scene.name.c_str(), all.frameMs / withoutEdges.frameMs, all.detectMs / withoutEdges.detectMs, all.edgeContacts);
    }
    if (scene.name.rfind("tori10-", 0) == 0)
    {
      const int k = scene.name == "tori10-pile" ? 0 : 1;
      tenToriFrameMs[k] = all.frameMs;
      tenToriDetectMs[k] = all.detectMs;
    }
    if (scene.name.rfind("tori-", 0) == 0)
    {
      const int k = scene.name == "tori-overlap" ? 0 : 1;
      toriFrameMs[k] = all.frameMs;
      toriDetectMs[k] = all.detectMs;
    }
    std::printf("%-12s collisions on / off: %.2f x the frame time (detection %.0f %%, contact solve %.0f %% of a frame); "
                "1 / %d threads: %.2f; same state at 1 and %d threads: %s\n",
      scene.name.c_str(), all.frameMs / off.frameMs, 100.0 * all.detectMs / all.frameMs, 100.0 * all.contactMs / all.frameMs,
      maxThreads, one.frameMs / all.frameMs, maxThreads, one.hash == all.hash ? "yes" : "NO");
    if (one.hash != all.hash)
    {
      status = 1; // parallel collision code must be deterministic
    }
    if (one.lowest < -0.01)
    {
      std::printf("ERROR: %s: a point fell %.4f m through the floor\n", scene.name.c_str(), -one.lowest);
      status = 1;
    }
  }
  std::printf("tori overlapping 0.25 m / touching: %.2f x the frame time, %.2f x the detection time\n",
    toriFrameMs[0] / toriFrameMs[1], toriDetectMs[0] / toriDetectMs[1]);
  std::printf("ten tori piled / apart: %.2f x the frame time, %.2f x the detection time\n",
    tenToriFrameMs[0] / tenToriFrameMs[1], tenToriDetectMs[0] / tenToriDetectMs[1]);
  // The ratios the documentation quotes, as a table of their own.
  table << "\n| measured in the same run (all threads) | frame time | detection time |\n|---|---|---|\n";
  std::snprintf(line, sizeof line, "| ten tori piled / apart | %.2f | %.2f |\n", tenToriFrameMs[0] / tenToriFrameMs[1],
    tenToriDetectMs[0] / tenToriDetectMs[1]);
  table << line;
  std::snprintf(line, sizeof line, "| two tori overlapping 0.25 m / touching | %.2f | %.2f |\n",
    toriFrameMs[0] / toriFrameMs[1], toriDetectMs[0] / toriDetectMs[1]);
  table << line;
  std::printf("CSV: %s\n", options.csv.c_str());
  return status;
}
