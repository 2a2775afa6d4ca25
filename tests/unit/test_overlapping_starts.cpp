// Bodies started inside each other: the set-up warning quotes how many
// points and how deep; the run steps with a bounded number of candidates and contacts per
// point (the cost stays with the contact surface), pushes the bodies apart no faster than
// kStartOverlapSeparationSpeed, and gives the same result at 1 and 2 threads.
#include "softbody/collision/contact_reduction.h"
#include "softbody/collision/start_overlap.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"
#include "softbody/pbd/pbd_simulation.h"
#include "test_support.h"
#include "torus_pair.h"

#include <tbb/global_control.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

using namespace softbody;

namespace
{

PbdSettings overlapSettings()
{
  PbdSettings s; // XPBD defaults
  s.floorEnabled = true;
  s.collisions.mode = CollisionMode::ObstaclesAndBodies;
  return s;
}

void appendMesh(Body& body, const TetMesh& mesh)
{
  const auto offset = static_cast<std::int32_t>(body.mesh.points.size());
  body.mesh.points.insert(body.mesh.points.end(), mesh.points.begin(), mesh.points.end());
  for (Tet t : mesh.tets)
  {
    for (std::int32_t& v : t)
      v += offset;
    body.mesh.tets.push_back(t);
  }
}

/// A 0.1 m tet cube (1 cm cells) and a 5 cm one standing 2.5 cm deep in its top, 2.5 cm from
/// its sides: 108 points of the small one lie inside the big one, 75 of the big one inside the
/// small one, the deepest of either 0.025 m below the other's surface (by construction).
Body nestedBoxes(double depth)
{
  Body body;
  appendMesh(body, makeTetBox(10, 10, 10, 0.01, Vec3(0.0, 0.0, 0.0)));
  appendMesh(body, makeTetBox(5, 5, 5, 0.01, Vec3(0.025, 0.025, 0.1 - depth)));
  return body;
}

std::size_t upperPointsInsideLower(const PbdSimulation& sim, const test::TorusPair& pair)
{
  CollisionGeometry g;
  g.rest = sim.restPositions();
  g.bodyOf.assign(g.rest.size(), 0);
  std::fill(g.bodyOf.begin() + static_cast<std::ptrdiff_t>(pair.lowerPoints), g.bodyOf.end(), 1);
  std::vector<Tet> lower(pair.body.mesh.tets.begin(), pair.body.mesh.tets.begin() + static_cast<std::ptrdiff_t>(pair.body.mesh.tets.size() / 2));
  g.surfaceTriangles = boundaryTriangles(lower);
  for (std::size_t i = pair.lowerPoints; i < g.rest.size(); ++i)
    g.collidingPoints.push_back(static_cast<std::int32_t>(i));
  const auto overlaps = findStartOverlaps(g, sim.positions());
  return overlaps.empty() ? 0 : overlaps[0].points;
}

struct ToriRun
{
  std::size_t mostExamined = 0, mostContacts = 0;
  double fastest = 0.0;  ///< largest point speed seen [m/s]
  double lowest = 1e9;   ///< lowest point seen [m]
  std::size_t insideAtStart = 0, insideAtEnd = 0;
  std::vector<Vec3> positions;
};

ToriRun runTori(double overlap, int steps)
{
  const test::TorusPair pair = test::torusPair(overlap);
  PbdSimulation sim(pair.body, overlapSettings());
  ToriRun run;
  run.insideAtStart = upperPointsInsideLower(sim, pair);
  for (int k = 0; k < steps; ++k)
  {
    sim.step(sim.stepSize());
    const DetectionStats& stats = sim.collisionDetector()->stats();
    run.mostExamined = std::max(run.mostExamined, stats.mostExaminedPerPoint);
    run.mostContacts = std::max(run.mostContacts, stats.mostContactsPerPoint);
    for (std::size_t i = 0; i < sim.positions().size(); ++i)
    {
      run.fastest = std::max(run.fastest, sim.velocities()[i].norm());
      run.lowest = std::min(run.lowest, sim.positions()[i].z());
    }
  }
  run.insideAtEnd = upperPointsInsideLower(sim, pair);
  run.positions = sim.positions();
  return run;
}

} // namespace

TEST(OverlappingStarts, WarningQuotesThePointsAndTheDepth)
{
  PbdSimulation nested(nestedBoxes(0.025), overlapSettings());
  std::string warning;
  for (const std::string& w : nested.warnings())
    warning += w.find("start inside each other") != std::string::npos ? w : "";
  std::printf("%s\n", warning.c_str());
  EXPECT_NE(warning.find("75 points of body 0 lie inside body 1, the deepest 0.025 m"), std::string::npos) << warning;
  EXPECT_NE(warning.find("108 points of body 1 lie inside body 0, the deepest 0.025 m"), std::string::npos) << warning;
  EXPECT_NE(warning.find("up to 0.5 m/s"), std::string::npos) << warning;
  EXPECT_NE(warning.find("apart by at least 0.025 m"), std::string::npos) << warning;
  // Boxes 1 mm apart do not overlap: no warning.
  PbdSimulation apart(nestedBoxes(-0.001), overlapSettings());
  for (const std::string& w : apart.warnings())
    EXPECT_EQ(w.find("start inside each other"), std::string::npos) << w;
}

TEST(OverlappingStarts, ReductionKeepsTheNearestFaceBehindAndAtMostFewPerSource)
{
  // One point against one body: six faces in front of it and five behind (the far side of a
  // tube it started inside), at distances 1..11 mm, given farthest first.
  std::vector<ContactCandidate> found;
  for (int k = 11; k >= 1; --k)
  {
    ContactCandidate c;
    c.contact.kind = ContactKind::PointTriangle;
    c.contact.point = 0;
    c.contact.source = 1;
    c.contact.other = { 3 * k, 3 * k + 1, 3 * k + 2 }; // no shared corners
    c.corners = c.contact.other;
    c.distance = 1e-3 * k;
    c.onFace = true;
    c.behind = c.startedBehind = k % 2 == 0; // 2, 4, ... 10 mm behind, from before the substep
    found.push_back(c);
  }
  std::vector<std::uint32_t> order, kept;
  ContactSet out;
  reduceCandidates(found, order, kept, out);
  ASSERT_EQ(out.size(), kMostContactsPerSource);
  // The nearest four, less the faces behind beyond the nearest one: 1, 2 (behind), 3, 5 mm.
  std::vector<int> distances;
  for (const Contact& c : out)
    distances.push_back(c.other[0] / 3);
  EXPECT_EQ(distances, (std::vector<int>{ 1, 2, 3, 5 }));
  // Faces it crossed in this substep (behind now, in front at its start) are all kept: 1-4 mm.
  for (ContactCandidate& c : found)
    c.startedBehind = false;
  out.clear();
  reduceCandidates(found, order, kept, out);
  distances.clear();
  for (const Contact& c : out)
    distances.push_back(c.other[0] / 3);
  EXPECT_EQ(distances, (std::vector<int>{ 1, 2, 3, 4 }));
}

TEST(OverlappingStarts, ToriStartedInsideEachOtherStepWithBoundedContactsAndSeparateSlowly)
{
  // 0.5 s: the pair falls, lands on the floor at ~0.25 s, and is pushed apart. Before the
  // bound, from ~0.5 s on every point examined all 3,361 triangles of the other torus and kept
  // up to 1,553 contacts, and the points flew at tens of m/s.
  const ToriRun run = runTori(0.25, 60);
  std::printf("overlapping tori: most examined %zu, most contacts %zu per point, fastest %.2f m/s, lowest %.4f m, "
              "upper points inside the lower %zu at the start, %zu after 0.5 s\n",
    run.mostExamined, run.mostContacts, run.fastest, run.lowest, run.insideAtStart, run.insideAtEnd);
  // Per point: the floor and at most kMostContactsPerSource on the other torus.
  EXPECT_LE(run.mostContacts, 1 + kMostContactsPerSource);
  EXPECT_LT(run.mostExamined, 200u); // a neighbourhood, not the other body (3,361 triangles)
  // Free fall from 0.3 m gives 2.4 m/s; the separation adds at most 0.5 m/s to each side.
  EXPECT_LT(run.fastest, std::sqrt(2 * 9.81 * 0.8) + 2 * kStartOverlapSeparationSpeed);
  EXPECT_GT(run.lowest, -0.01);
  EXPECT_GT(run.insideAtStart, 400u);
  EXPECT_LT(run.insideAtEnd, run.insideAtStart / 10); // apart, not entangled
}

TEST(OverlappingStarts, OverlappingToriGiveTheSameResultAtOneAndTwoThreads)
{
  auto at = [](std::size_t threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    return runTori(0.25, 40).positions;
  };
  const std::vector<Vec3> one = at(1), two = at(2);
  EXPECT_TRUE(test::bitwiseEqual(one, two)) << test::maxDistance(one, two);
}

TEST(OverlappingStarts, MassSpringToriStartedInsideEachOtherStepWithBoundedContacts)
{
  // The same detector serves mass-spring: the same bounds per point, and no burst.
  const test::TorusPair pair = test::torusPair(0.25);
  Body body;
  body.mesh = TetMesh{ pair.body.mesh.points, pair.body.mesh.tets };
  SceneSettings scene;
  scene.floorEnabled = true;
  scene.collisions.mode = CollisionMode::ObstaclesAndBodies;
  MassSpringSimulation sim(body, scene);
  std::size_t mostExamined = 0, mostContacts = 0;
  double fastest = 0.0;
  for (int frame = 1; frame <= 10; ++frame)
  {
    sim.advance(0.05 * frame);
    const DetectionStats& stats = sim.collisionDetector()->stats();
    mostExamined = std::max(mostExamined, stats.mostExaminedPerPoint);
    mostContacts = std::max(mostContacts, stats.mostContactsPerPoint);
    for (const Vec3& v : sim.velocities())
      fastest = std::max(fastest, v.norm());
  }
  std::printf("mass-spring overlapping tori: step %.2e s, most examined %zu, most contacts %zu per point, fastest %.2f m/s\n",
    sim.stepSize(), mostExamined, mostContacts, fastest);
  EXPECT_LE(mostContacts, 1 + kMostContactsPerSource);
  EXPECT_LT(mostExamined, 200u);
  EXPECT_LT(fastest, 10.0); // free fall from under 1 m: 4.4 m/s
}

TEST(OverlappingStarts, ABodyStartedAcrossAnObstacleIsWarnedOfAndPulledAcrossItWithoutCrushing)
{
  // A TetGen torus (about 0.36 m tall: ring 0.2 m, tube 0.08 m, tilted 30 deg) whose lowest
  // point starts 0.25 m under a 20-degree ramp obstacle: the set-up warns with the points behind it and the depth. Placed 0.1 m above the
  // ramp, or wholly under it (a body under a roof), nothing is said. The run that follows pulls
  // the torus across the one-sided ramp (out where it is shallow, through where deep) and must
  // stay finite without inverting more than a few percent of its tets.
  const double pi = std::acos(-1.0), angle = 20.0 * pi / 180.0;
  const Vec3 n(std::sin(angle), 0.0, std::cos(angle)), centre(0.0, 0.0, 0.6);
  ObstacleSurface quad;
  const Vec3 u = 1.5 * Vec3(std::cos(angle), 0.0, -std::sin(angle)), v(0.0, 1.5, 0.0);
  quad.vertices = { centre - u - v, centre + u - v, centre + u + v, centre - u + v };
  quad.triangles = { { 0, 1, 2 }, { 0, 2, 3 } };
  auto placed = [&](double lowestAboveRamp) {
    Body body;
    body.mesh = test::tetTorus(1e-4);
    double lowest = 1e300;
    for (const Vec3& p : body.mesh.points)
    {
      lowest = std::min(lowest, (p - centre).dot(n));
    }
    for (Vec3& p : body.mesh.points)
    {
      p += (lowestAboveRamp - lowest) * n;
    }
    return body;
  };
  auto simulation = [&](const Body& body) {
    SceneSettings scene;
    scene.integrator = Integrator::ImplicitEuler;
    scene.timeStep = 1.0 / 30.0;
    scene.floorEnabled = true;
    scene.collisions.staticFriction = scene.collisions.dynamicFriction = 0.3;
    auto sim = std::make_unique<MassSpringSimulation>(body, scene);
    sim->setObstacles({ quad }, 0.0);
    return sim;
  };
  auto warnsOfObstacle = [](const MassSpringSimulation& sim) {
    for (const std::string& w : sim.warnings())
    {
      if (w.find("start behind the surface of obstacle 0") != std::string::npos)
      {
        return w;
      }
    }
    return std::string();
  };
  auto across = simulation(placed(-0.25));
  const std::string warning = warnsOfObstacle(*across);
  std::printf("  %s\n", warning.c_str());
  EXPECT_NE(warning.find("the deepest 0.25 m"), std::string::npos) << warning;
  EXPECT_TRUE(warnsOfObstacle(*simulation(placed(0.1))).empty());
  EXPECT_TRUE(warnsOfObstacle(*simulation(placed(-1.0))).empty()) << "wholly under the ramp";

  std::size_t worst = 0;
  for (int frame = 1; frame <= 30; ++frame)
  {
    across->advance(frame / 30.0);
    const std::vector<double> ratios = across->tetVolumeRatios();
    worst = std::max(worst, static_cast<std::size_t>(std::count_if(ratios.begin(), ratios.end(), [](double r) { return r <= 0.0; })));
  }
  double lowest = 1e300, highest = -1e300;
  for (const Vec3& p : across->positions())
  {
    EXPECT_TRUE(p.allFinite());
    lowest = std::min(lowest, (p - centre).dot(n));
    highest = std::max(highest, (p - centre).dot(n));
  }
  std::printf("  after 1 s: at most %zu of %zu tets inverted in a frame; points from %.3f to %.3f m off the ramp's plane\n",
    worst, across->tetVolumeRatios().size(), lowest, highest);
  // Measured 149 of 3,944 (3.8 %) under Implicit Euler at 1/30 s.
  EXPECT_LE(worst, across->tetVolumeRatios().size() / 20);
}
