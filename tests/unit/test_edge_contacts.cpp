// Edge against edge: two bars crossed at right angles, each turned 45 degrees
// about its length so that a ridge faces the other, meet ridge on ridge with every vertex of
// each outside the other's cross-section: only an edge-edge contact can hold them. The
// detector reports it (and the same set for every broad phase); the mass-spring response
// (explicit and implicit) and XPBD hold the upper bar on the lower one, and without edge
// contacts it falls through (the control).
#include "softbody/collision/closest_point.h"
#include "softbody/collision/collision_detector.h"
#include "softbody/collision/contact_terms.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"
#include "softbody/pbd/pbd_simulation.h"
#include "collision_test_scenes.h"
#include "torus_pair.h"

#include <tbb/global_control.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

using namespace softbody;

namespace
{

constexpr double kHalfWidth = 0.025; ///< half the bars' square cross-section [m]
constexpr double kCell = 0.1;        ///< the bars' cell length [m]: vertices 5 cm either side of the crossing
const double kRidge = kHalfWidth * std::sqrt(2.0); ///< ridge height above a bar's axis [m]

/// A bar of 5 cells along `axis` (0 = x, 1 = y) with a square cross-section turned 45 degrees
/// about its length: one ridge on top (ridgeUp) or at the bottom, on the line through `center`.
/// Its vertices along the ridge lie at +-0.05, +-0.15, +-0.25 m from the centre.
TetMesh ridgeBar(int axis, bool ridgeUp, const Vec3& center)
{
  TetMesh mesh = axis == 0 ? makeTetBox(5, 1, 1, 1.0) : makeTetBox(1, 5, 1, 1.0);
  const double c = std::sqrt(0.5);
  for (Vec3& p : mesh.points)
  {
    const double along = kCell * ((axis == 0 ? p.x() : p.y()) - 2.5);
    const double across = 2.0 * kHalfWidth * ((axis == 0 ? p.y() : p.x()) - 0.5);
    const double up = 2.0 * kHalfWidth * (p.z() - 0.5);
    // Turned (a rotation, so the tets keep their orientation) so that the corner
    // (across, up) = (s, s) goes straight up (s > 0), or half a turn more, straight down.
    const double sign = ridgeUp ? 1.0 : -1.0;
    const double turnedAcross = sign * c * (across - up);
    const double turnedUp = sign * c * (across + up);
    p = center + (axis == 0 ? Vec3(along, turnedAcross, turnedUp) : Vec3(turnedAcross, along, turnedUp));
  }
  return mesh;
}

/// The bars' ridge: its points along the bar, in order (`bar` rotated as in ridgeBar).
std::vector<std::int32_t> ridgeOf(const TetMesh& bar, int axis, bool ridgeUp, std::int32_t offset)
{
  std::vector<std::int32_t> points;
  double extreme = ridgeUp ? -1e300 : 1e300;
  for (const Vec3& p : bar.points)
  {
    extreme = ridgeUp ? std::max(extreme, p.z()) : std::min(extreme, p.z());
  }
  for (std::size_t i = 0; i < bar.points.size(); ++i)
  {
    if (std::abs(bar.points[i].z() - extreme) < 1e-12)
    {
      points.push_back(static_cast<std::int32_t>(i) + offset);
    }
  }
  std::sort(points.begin(), points.end(), [&](std::int32_t a, std::int32_t b) {
    return bar.points[a - offset][axis] < bar.points[b - offset][axis];
  });
  return points;
}

/// An upper bar along x, ridge down, lying `gap` above the ridges of `rails` bars along y,
/// ridge up, whose ends are pinned: one rail under its middle, or two (at x = -0.1 and 0.1,
/// mid-cell of the upper bar's ridge) for a stable rest.
struct CrossedBars
{
  TetMesh mesh; ///< the bars one after the other, the upper one first
  std::vector<std::size_t> firstPoint; ///< per bar, and the end
  std::vector<std::size_t> firstTet;
  std::vector<std::vector<std::int32_t>> ridges; ///< per bar
  std::vector<char> pinned;
};

CrossedBars crossedBars(double gap, int rails)
{
  CrossedBars bars;
  auto add = [&](const TetMesh& bar, int axis, bool ridgeUp, bool pinEnds) {
    const auto offset = static_cast<std::int32_t>(bars.mesh.points.size());
    bars.firstPoint.push_back(bars.mesh.points.size());
    bars.firstTet.push_back(bars.mesh.tets.size());
    bars.ridges.push_back(ridgeOf(bar, axis, ridgeUp, offset));
    for (const Vec3& p : bar.points)
    {
      bars.mesh.points.push_back(p);
      bars.pinned.push_back(pinEnds && std::abs(std::abs(p.y()) - 0.25) < 1e-9 ? 1 : 0);
    }
    for (Tet t : bar.tets)
    {
      for (auto& v : t)
      {
        v += offset;
      }
      bars.mesh.tets.push_back(t);
    }
  };
  add(ridgeBar(0, false, Vec3(0.0, 0.0, gap + kRidge)), 0, false, false);
  for (int r = 0; r < rails; ++r)
  {
    const double x = rails == 1 ? 0.0 : (r == 0 ? -0.1 : 0.1);
    add(ridgeBar(1, true, Vec3(x, 0.0, -kRidge)), 1, true, true);
  }
  bars.firstPoint.push_back(bars.mesh.points.size());
  bars.firstTet.push_back(bars.mesh.tets.size());
  return bars;
}

/// How far the upper ridge is above the lower one `rail` where they cross (negative: through
/// it): the closest points of the two ridge polylines where both lie inside, signed by which
/// is higher; +infinity once they no longer cross.
double ridgeGap(const std::vector<Vec3>& x, const std::vector<std::int32_t>& upper, const std::vector<std::int32_t>& lower)
{
  double best = 1e300, signedGap = 1e300;
  for (std::size_t i = 0; i + 1 < upper.size(); ++i)
  {
    for (std::size_t j = 0; j + 1 < lower.size(); ++j)
    {
      const Vec3 &a0 = x[upper[i]], &a1 = x[upper[i + 1]], &b0 = x[lower[j]], &b1 = x[lower[j + 1]];
      const SegmentPair w = closestPointsOfSegments(a0, a1, b0, b1);
      const Vec3 d = a0 + w.s * (a1 - a0) - b0 - w.t * (b1 - b0);
      if (w.s > 0.0 && w.s < 1.0 && w.t > 0.0 && w.t < 1.0 && d.norm() < best)
      {
        best = d.norm();
        signedGap = d.z() >= 0.0 ? best : -best;
      }
    }
  }
  return signedGap;
}

/// The lowest ridge gap over all rails.
double lowestRidgeGap(const std::vector<Vec3>& x, const CrossedBars& bars)
{
  double lowest = 1e300;
  for (std::size_t r = 1; r < bars.ridges.size(); ++r)
  {
    lowest = std::min(lowest, ridgeGap(x, bars.ridges[0], bars.ridges[r]));
  }
  return lowest;
}

CollisionGeometry barsGeometry(const CrossedBars& bars)
{
  CollisionGeometry g;
  for (std::size_t b = 0; b + 1 < bars.firstPoint.size(); ++b)
  {
    TetMesh bar;
    bar.points.assign(bars.mesh.points.begin() + static_cast<std::ptrdiff_t>(bars.firstPoint[b]),
      bars.mesh.points.begin() + static_cast<std::ptrdiff_t>(bars.firstPoint[b + 1]));
    for (std::size_t t = bars.firstTet[b]; t < bars.firstTet[b + 1]; ++t)
    {
      Tet tet = bars.mesh.tets[t];
      for (auto& v : tet)
      {
        v -= static_cast<std::int32_t>(bars.firstPoint[b]);
      }
      bar.tets.push_back(tet);
    }
    test::addTetBody(g, bar, static_cast<std::int32_t>(b));
  }
  return g;
}

/// The bars as one XPBD body (the rails' ends pinned), and XPBD defaults without a floor.
Body barsBody(const CrossedBars& bars)
{
  Body body;
  body.mesh.points = bars.mesh.points;
  body.mesh.tets = bars.mesh.tets;
  body.pinned = bars.pinned;
  return body;
}

PbdSettings barsSettings(CollisionMode mode, double margin)
{
  PbdSettings settings;
  settings.floorEnabled = false;
  settings.collisions.mode = mode;
  settings.collisions.margin = margin;
  return settings;
}

} // namespace

TEST(EdgeContacts, RidgesCrossingInASubstepAreCaughtAsOneEdgeContactWithTheNormalTheyCameFrom)
{
  const CrossedBars bars = crossedBars(0.01, 1);
  const CollisionGeometry g = barsGeometry(bars);
  std::vector<Vec3> predicted = bars.mesh.points;
  for (std::size_t i = 0; i < bars.firstPoint[1]; ++i)
  {
    predicted[i].z() -= 0.015; // through the lower ridge by 5 mm within the substep
  }
  auto detect = [&](BroadPhase broadPhase, bool edges) {
    CollisionSettings settings;
    settings.mode = CollisionMode::ObstaclesAndBodies;
    settings.margin = 0.001;
    settings.broadPhase = broadPhase;
    settings.edgeContacts = edges;
    CollisionDetector detector(g, settings, false, FloorPlane{});
    ContactSet contacts;
    detector.detect(bars.mesh.points, predicted, 0.0, 0.01, contacts);
    return contacts;
  };
  const ContactSet contacts = detect(BroadPhase::UniformGrid, true);
  // The sweep also reports speculative contacts (C > 0: the face diagonals near the crossing,
  // within the substep's motion); the one that is violated is the ridges'.
  std::size_t violated = 0;
  for (const Contact& c : contacts)
  {
    ASSERT_EQ(c.kind, ContactKind::EdgeEdge) << "no vertex is near a face: only edges meet";
    const ContactTerms terms = termsOf(c);
    Vec3 r = Vec3::Zero();
    for (int j = 0; j < terms.count; ++j)
    {
      r += terms.coefficient[j] * predicted[terms.index[j]];
    }
    if (c.normal.dot(r) - c.thickness >= 0.0)
    {
      continue;
    }
    ++violated;
    EXPECT_NEAR(c.normal.z(), 1.0, 1e-12); // from the lower ridge up to the upper one
    EXPECT_NEAR(c.barycentric[0], 0.5, 1e-9); // both in the middle of their edges
    EXPECT_NEAR(c.barycentric[1], 0.5, 1e-9);
    EXPECT_NEAR(c.normal.dot(r) - c.thickness, -0.005 - 0.001, 1e-12); // 5 mm through, and the margin
    EXPECT_LT(c.point, static_cast<std::int32_t>(bars.firstPoint[1]));
    EXPECT_EQ(c.source, 1);
  }
  EXPECT_EQ(violated, 1u);
  EXPECT_TRUE(test::sameContacts(contacts, detect(BroadPhase::BruteForce, true)));
  EXPECT_TRUE(test::sameContacts(contacts, detect(BroadPhase::Octree, true)));
  EXPECT_TRUE(detect(BroadPhase::UniformGrid, false).empty()); // the control: nothing else sees them
}

TEST(EdgeContacts, RidgesThatStartedThroughEachOtherAreLeftToTheirPointContacts)
{
  // The upper bar placed 1 cm through the lower one: the ridges' start direction points into
  // the bodies, so no edge contact would keep them crossed (the point pass separates bodies
  // started inside each other).
  const CrossedBars bars = crossedBars(-0.01, 1);
  CollisionSettings settings;
  settings.mode = CollisionMode::ObstaclesAndBodies;
  settings.margin = 0.001;
  CollisionDetector detector(barsGeometry(bars), settings, false, FloorPlane{});
  ContactSet contacts;
  detector.detect(bars.mesh.points, bars.mesh.points, 0.0, 0.01, contacts);
  for (const Contact& c : contacts)
  {
    EXPECT_NE(c.kind, ContactKind::EdgeEdge);
  }
}

TEST(EdgeContacts, ABarDroppedAcrossTwoRidgesRestsOnThemUnderEveryMethodAndFallsThroughWithoutThem)
{
  const double margin = 0.002;
  const CrossedBars bars = crossedBars(0.01, 2);
  ASSERT_EQ(bars.ridges.size(), 3u);
  for (const auto& r : bars.ridges)
  {
    ASSERT_EQ(r.size(), 6u);
  }
  auto lowestGap = [&](auto& sim) {
    double lowest = 1e300;
    for (int k = 1; k <= 25; ++k)
    {
      sim.advance(0.02 * k);
      lowest = std::min(lowest, lowestRidgeGap(sim.positions(), bars));
    }
    return lowest;
  };
  auto massSpring = [&](Integrator integrator, bool edges) {
    Body body;
    body.mesh = bars.mesh;
    body.pinned = bars.pinned;
    SceneSettings scene;
    scene.floorEnabled = false;
    scene.integrator = integrator;
    scene.timeStep = integrator == Integrator::ImplicitEuler ? 1.0 / 200.0 : 0.0;
    scene.collisions.mode = CollisionMode::ObstaclesAndBodies;
    scene.collisions.margin = margin;
    scene.collisions.edgeContacts = edges;
    MassSpringSimulation sim(body, scene);
    return lowestGap(sim);
  };
  auto xpbd = [&](bool edges) {
    PbdSettings settings = barsSettings(CollisionMode::ObstaclesAndBodies, margin);
    settings.collisions.edgeContacts = edges;
    PbdSimulation sim(barsBody(bars), settings);
    return lowestGap(sim);
  };
  const double explicitGap = massSpring(Integrator::EulerCromer, true);
  const double implicitGap = massSpring(Integrator::ImplicitEuler, true);
  const double xpbdGap = xpbd(true);
  const double withoutEdges = massSpring(Integrator::EulerCromer, false);
  const double xpbdWithoutEdges = xpbd(false);
  std::printf("  lowest ridge gap over 0.5 s (margin %.0e m): Euler-Cromer %.2e, Implicit Euler %.2e, "
              "XPBD %.2e m; without edge contacts %.2e and %.2e m\n",
    margin, explicitGap, implicitGap, xpbdGap, withoutEdges, xpbdWithoutEdges);
  // Held apart by the margin the contact keeps (the projection puts the ridges on it).
  EXPECT_GT(explicitGap, 0.5 * margin);
  EXPECT_GT(implicitGap, 0.5 * margin);
  EXPECT_GT(xpbdGap, 0.5 * margin);
  // The controls: nothing else holds the ridges, and the upper bar goes through.
  EXPECT_LT(withoutEdges, -kHalfWidth);
  EXPECT_LT(xpbdWithoutEdges, -kHalfWidth);
}

TEST(EdgeContacts, OneAndTwoThreadsGiveBitIdenticalStates)
{
  // The bar on the ridges under XPBD, with the edge pass's blocks split over threads.
  const CrossedBars bars = crossedBars(0.01, 2);
  auto run = [&](std::size_t threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    PbdSimulation sim(barsBody(bars), barsSettings(CollisionMode::ObstaclesBodiesAndSelf, 0.002));
    sim.advance(0.2);
    return sim.positions();
  };
  const std::vector<Vec3> one = run(1);
  const std::vector<Vec3> two = run(2);
  ASSERT_EQ(one.size(), two.size());
  EXPECT_TRUE(std::equal(one.begin(), one.end(), two.begin(), [](const Vec3& a, const Vec3& b) { return a == b; }));
}

TEST(EdgeContacts, TheTreesFindWhatBruteForceFindsOnTwoTetGenToriMovingIntoEachOther)
{
  // Surface edges query the other bodies' trees in groups, with their tree node's box
  // (TriangleBvh::groups); each edge then box-tests what its group found. That must leave each
  // edge the candidates it would meet alone, in the same order: the contacts equal brute
  // force's bit for bit, with and without self collisions, at 1 and 2 threads.
  const test::TorusPair pair = test::torusPair(0.0, 2e-4); // about 500 points each
  const auto lowerPoints = static_cast<std::int32_t>(pair.lowerPoints);
  CollisionGeometry g;
  for (int body = 0; body < 2; ++body)
  {
    TetMesh torus;
    const std::int32_t first = body == 0 ? 0 : lowerPoints;
    const auto last = body == 0 ? lowerPoints : static_cast<std::int32_t>(pair.body.mesh.points.size());
    torus.points.assign(pair.body.mesh.points.begin() + first, pair.body.mesh.points.begin() + last);
    for (Tet t : pair.body.mesh.tets)
    {
      if (t[0] >= first && t[0] < last)
      {
        for (std::int32_t& v : t)
        {
          v -= first;
        }
        torus.tets.push_back(t);
      }
    }
    test::addTetBody(g, torus, body);
  }
  // The upper torus moves 10 cm down into the lower one over the substep, every point jittered
  // by up to 1 mm (surface edges cross at all angles).
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.001, 0.001);
  std::vector<Vec3> start = g.rest, predicted = g.rest;
  for (std::size_t i = 0; i < predicted.size(); ++i)
  {
    start[i] += Vec3(jitter(rng), jitter(rng), jitter(rng));
    predicted[i] = start[i] + Vec3(jitter(rng), jitter(rng), jitter(rng) - (static_cast<std::int32_t>(i) >= lowerPoints ? 0.1 : 0.0));
  }
  auto detect = [&](BroadPhase kind, CollisionMode mode, std::size_t threads, std::size_t& edgeContacts) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    CollisionSettings settings;
    settings.mode = mode;
    settings.broadPhase = kind;
    settings.margin = 0.002;
    CollisionDetector detector(g, settings, false, FloorPlane{});
    ContactSet contacts;
    detector.detect(g.rest, start, 0.0, 0.01, contacts); // builds the trees; the second detection refits them
    detector.detect(start, predicted, 0.01, 0.01, contacts);
    edgeContacts = detector.stats().edgeContacts;
    return contacts;
  };
  for (CollisionMode mode : { CollisionMode::ObstaclesAndBodies, CollisionMode::ObstaclesBodiesAndSelf })
  {
    std::size_t bruteEdges = 0;
    const ContactSet reference = detect(BroadPhase::BruteForce, mode, 2, bruteEdges);
    std::printf("%s: %zu contacts, %zu of them edge against edge\n",
      mode == CollisionMode::ObstaclesAndBodies ? "bodies" : "bodies and self", reference.size(), bruteEdges);
    EXPECT_GT(bruteEdges, 200u) << "mode " << static_cast<int>(mode);
    for (BroadPhase kind : { BroadPhase::UniformGrid, BroadPhase::Octree })
    {
      for (std::size_t threads : { 1u, 2u })
      {
        std::size_t edges = 0;
        const ContactSet contacts = detect(kind, mode, threads, edges);
        EXPECT_EQ(edges, bruteEdges);
        EXPECT_TRUE(test::sameContacts(contacts, reference))
          << "broad phase " << static_cast<int>(kind) << ", mode " << static_cast<int>(mode) << ", " << threads
          << " threads: " << contacts.size() << " contacts against " << reference.size();
      }
    }
  }
}
