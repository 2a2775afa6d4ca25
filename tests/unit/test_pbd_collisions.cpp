// PBD/XPBD contacts as a whole: friction on an inclined obstacle against Coulomb's law,
// restitution of particle and tet bodies, bodies on bodies, self-collision of a folded bar and
// of a cloth on a sphere, a moving obstacle, pre-stabilization below the floor, determinism.
#include "softbody/pbd/cloth.h"
#include "softbody/pbd/pbd_reordered.h"
#include "softbody/pbd/pbd_simulation.h"
#include "pbd_collision_scenes.h"
#include "pbd_test_bodies.h"
#include "test_support.h"

#include <tbb/global_control.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace softbody
{
namespace
{
constexpr double kG = 9.81;

Vec3 centroid(const std::vector<Vec3>& x, std::size_t begin = 0, std::size_t end = 0)
{
  end = end == 0 ? x.size() : end;
  Vec3 c = Vec3::Zero();
  for (std::size_t i = begin; i < end; ++i)
  {
    c += x[i];
  }
  return c / static_cast<double>(end - begin);
}

Vec3 meanVelocity(const PbdSimulation& sim)
{
  return centroid(sim.velocities());
}

/// Stiff PBD (stiffness 1) at 1 ms steps with an explicit contact margin.
PbdSettings contactSettings(double margin = 0.002)
{
  PbdSettings s;
  s.formulation = PbdFormulation::Pbd;
  s.timeStep = 1e-3;
  s.collisions.margin = margin;
  return s;
}

/// Slide distance of a 0.1 x 0.1 x 0.05 m tet block after `T` s on a quad obstacle tilted by
/// theta, with mu_s = mu_k = mu; it starts at rest on the quad (at the contact margin).
double slideOnIncline(double thetaDegrees, double mu, double T)
{
  const double theta = thetaDegrees * M_PI / 180.0, c = std::cos(theta), s = std::sin(theta);
  Eigen::Matrix3d R;
  R << c, 0, s, 0, 1, 0, -s, 0, c;
  PbdSettings settings = contactSettings();
  settings.collisions.staticFriction = settings.collisions.dynamicFriction = mu;
  Body body = test::pbdBoxBody(2, 0.05, Vec3(-0.05, -0.05, settings.collisions.margin));
  for (Vec3& p : body.mesh.points)
  {
    p = R * p;
  }
  PbdSimulation sim(body, settings);
  sim.setObstacles({ test::quadObstacle(Vec3::Zero(), R * Vec3(2, 0, 0), Vec3(0, 2, 0)) }, 0.0);
  const Vec3 start = centroid(sim.positions());
  sim.advance(T);
  return (centroid(sim.positions()) - start).dot(R * Vec3(1, 0, 0));
}

TEST(PbdCollisions, BlockOnAnInclinedObstacleFollowsCoulomb)
{
  // Sliding: s = a T^2 / 2 with a = g (sin theta - mu cos theta).
  const double theta = 30.0, mu = 0.3, T = 0.4;
  const double a = kG * (std::sin(theta * M_PI / 180) - mu * std::cos(theta * M_PI / 180));
  const double slid = slideOnIncline(theta, mu, T);
  std::printf("slid %.4f m in %.1f s, Coulomb %.4f m\n", slid, T, 0.5 * a * T * T);
  EXPECT_NEAR(slid, 0.5 * a * T * T, 0.03 * 0.5 * a * T * T);
  // Frictionless it slides at g sin theta: the friction above is what slowed it.
  const double free = slideOnIncline(theta, 0.0, T);
  EXPECT_NEAR(free, 0.5 * kG * 0.5 * T * T, 0.03 * 0.5 * kG * 0.5 * T * T);
  // Sticking: tan 20 deg = 0.36 <= 0.5 and tan 30 deg = 0.577 <= 0.6: it does not move.
  EXPECT_LT(std::abs(slideOnIncline(20.0, 0.5, T)), 1e-4);
  EXPECT_LT(std::abs(slideOnIncline(30.0, 0.6, T)), 1e-4);
}

/// Rebound of the centre of mass above where the body rests after falling h onto a horizontal
/// quad obstacle (not the floor: the obstacle path).
double reboundOnObstacle(Body body, PbdSettings settings, double restitution, double h)
{
  settings.collisions.restitution = restitution;
  PbdSimulation sim(std::move(body), settings);
  sim.setObstacles({ test::quadObstacle(Vec3::Zero(), Vec3(2, 0, 0), Vec3(0, 2, 0)) }, 0.0);
  const double resting = centroid(sim.positions()).z() - h;
  bool bounced = false;
  double top = -1.0;
  for (int s = 0; s < 2000; ++s)
  {
    sim.step(1e-3);
    const double z = centroid(sim.positions()).z(), vz = meanVelocity(sim).z();
    bounced = bounced || (vz > 0.0 && z < resting + 0.05);
    if (bounced)
    {
      top = std::max(top, z);
      if (vz < 0.0)
      {
        break;
      }
    }
  }
  return bounced ? top - resting : 0.0;
}

TEST(PbdCollisions, RestitutionGivesAReboundOfESquaredHForParticleAndTetBodies)
{
  const double h = 0.3, e = 0.5;
  // A particle body: 3 x 3 x 3 particles of radius 0.025, their bottom layer h above where
  // it rests (radius + margin over the quad).
  PbdSettings particles = contactSettings();
  particles.particleRadius = 0.025;
  const double rest = particles.particleRadius + particles.collisions.margin;
  const Body lattice = test::particleBlock(3, 0.05, Vec3(-0.05, -0.05, rest + h));
  // A tet body: a 0.1 m cube, its bottom h above the margin.
  PbdSettings tets = contactSettings();
  const Body cube = test::pbdBoxBody(2, 0.05, Vec3(-0.05, -0.05, tets.collisions.margin + h));
  for (const auto& [name, body, settings] :
    { std::tuple{ "particles", lattice, particles }, std::tuple{ "tets", cube, tets } })
  {
    const double bounce = reboundOnObstacle(body, settings, e, h);
    const double none = reboundOnObstacle(body, settings, 0.0, h);
    std::printf("%s: rebound %.4f m (e = %.1f, e^2 h = %.4f), %.4f m (e = 0)\n", name, bounce, e,
      e * e * h, none);
    EXPECT_NEAR(bounce, e * e * h, 0.15 * e * e * h) << name;
    EXPECT_LT(none, 0.2 * e * e * h) << name;
  }
}

TEST(PbdCollisions, BodiesDroppedOntoEachOtherNeverInterpenetrate)
{
  // A tet cube resting on the floor; a smaller tet cube and a particle block fall onto it.
  PbdSettings settings = contactSettings();
  settings.floorEnabled = true;
  settings.particleRadius = 0.02;
  settings.collisions.mode = CollisionMode::ObstaclesAndBodies;
  const double margin = settings.collisions.margin;
  Body scene = test::pbdBoxBody(3, 0.1, Vec3(-0.15, -0.15, margin)); // top at 0.3 + margin
  const std::size_t cubeEnd = scene.mesh.points.size();
  Body small = test::pbdBoxBody(2, 0.05, Vec3(-0.1, -0.05, 0.45));
  Body block = test::particleBlock(3, 0.04, Vec3(0.04, -0.04, 0.5), 0.5);
  // Masses for the tet parts (the particle block brings its own).
  scene.pointMass.assign(scene.mesh.points.size(), 27.0 / double(scene.mesh.points.size()));
  small.pointMass.assign(small.mesh.points.size(), 0.125 / double(small.mesh.points.size()));
  test::appendBody(scene, small);
  const std::size_t smallEnd = scene.mesh.points.size();
  test::appendBody(scene, block);
  PbdSimulation sim(scene, settings);
  const double cubeTop = 0.3 + margin;
  double worstSmall = 1.0, worstBlock = 1.0;
  std::size_t bodyContacts = 0;
  for (int s = 0; s < 1000; ++s)
  {
    sim.step(1e-3);
    const auto& x = sim.positions();
    double top = -1.0;
    for (std::size_t i = 0; i < cubeEnd; ++i)
    {
      top = std::max(top, x[i].z());
    }
    double smallBottom = 1.0, blockBottom = 1.0;
    for (std::size_t i = cubeEnd; i < x.size(); ++i)
    {
      (i < smallEnd ? smallBottom : blockBottom) =
        std::min(i < smallEnd ? smallBottom : blockBottom, x[i].z() - (i < smallEnd ? 0.0 : settings.particleRadius));
    }
    worstSmall = std::min(worstSmall, smallBottom - top);
    worstBlock = std::min(worstBlock, blockBottom - top);
    for (const Contact& c : sim.contacts())
    {
      bodyContacts += c.kind != ContactKind::Obstacle ? 1 : 0;
    }
  }
  std::printf("closest approach to the cube's top: tet cube %.2e m, particle block %.2e m "
              "(margin %.0e m); cube top %.4f m\n", worstSmall, worstBlock, margin, cubeTop);
  EXPECT_GT(bodyContacts, 0u);
  EXPECT_GT(worstSmall, -margin);
  EXPECT_GT(worstBlock, -margin);
  // ... and they came to rest on it, not above it.
  const auto& x = sim.positions();
  EXPECT_LT(centroid(x, cubeEnd, smallEnd).z(), cubeTop + 0.05 + 3 * margin);
  EXPECT_LT(centroid(x, smallEnd, x.size()).z(), cubeTop + 0.04 + settings.particleRadius + 3 * margin);
}

TEST(PbdCollisions, ParticleBodyStartingBelowTheFloorEndsOnItWithoutGainingSpeed)
{
  PbdSettings settings = contactSettings();
  settings.floorEnabled = true;
  settings.particleRadius = 0.025;
  PbdSimulation sim(test::particleBlock(3, 0.05, Vec3(-0.05, -0.05, -0.05)), settings);
  const double floorRest = settings.particleRadius + settings.collisions.margin;
  double lowest = 1.0;
  for (const Vec3& p : sim.positions())
  {
    lowest = std::min(lowest, p.z());
  }
  EXPECT_NEAR(lowest, floorRest, 1e-12); // lifted rigidly onto the contact thickness
  double maxUp = 0.0;
  for (int s = 0; s < 500; ++s)
  {
    sim.step(1e-3);
    for (const Vec3& v : sim.velocities())
    {
      maxUp = std::max(maxUp, v.z());
    }
  }
  std::printf("max upward particle speed %.3g m/s\n", maxUp);
  EXPECT_LT(maxUp, 0.05);
  EXPECT_NEAR(centroid(sim.positions()).z(), floorRest + 0.05, 2e-3);
}

TEST(PbdCollisions, MovingObstaclePushesABody)
{
  // A wall moving at 0.5 m/s along +x meets a cube resting on the frictionless floor 5 cm in
  // front of it; after 0.5 s the cube moves with the wall, in front of it.
  PbdSettings settings = contactSettings();
  settings.floorEnabled = true;
  const double margin = settings.collisions.margin;
  PbdSimulation sim(test::pbdBoxBody(2, 0.05, Vec3(0.0, -0.05, margin)), settings);
  const double speed = 0.5, start = -0.05;
  for (int frame = 1; frame <= 25; ++frame)
  {
    const double t = frame * 0.02;
    ObstacleSurface wall = test::quadObstacle(Vec3(start + speed * t, 0, 0.2), Vec3(0, 0.5, 0), Vec3(0, 0, 0.3));
    wall.velocities.assign(wall.vertices.size(), Vec3(speed, 0, 0));
    sim.setObstacles({ wall }, t);
    sim.advance(t);
  }
  const double wallX = start + speed * 0.5;
  double back = 1.0;
  for (const Vec3& p : sim.positions())
  {
    back = std::min(back, p.x());
  }
  std::printf("wall at %.4f m, cube's back at %.4f m, cube speed %.3f m/s\n", wallX, back, meanVelocity(sim).x());
  EXPECT_GT(back, wallX + 0.5 * margin); // never behind the wall
  EXPECT_LT(back, wallX + 0.02);         // it started 5 cm ahead: pushed along
  EXPECT_NEAR(meanVelocity(sim).x(), speed, 0.05);
}

TEST(PbdCollisions, ClothFallingOnASphereNeitherCrossesItNorItself)
{
  ClothSpec spec;
  spec.particlesAlong1 = spec.particlesAlong2 = 12;
  spec.origin = Vec3(-0.5, -0.5, 0.45);
  spec.point1 = Vec3(0.5, -0.5, 0.45);
  spec.point2 = Vec3(-0.5, 0.5, 0.45);
  spec.diagonalStiffness = 0.2;
  const Body cloth = makeCloth(spec);
  PbdSettings settings = contactSettings(0.01);
  settings.collisions.mode = CollisionMode::ObstaclesBodiesAndSelf;
  settings.collisions.staticFriction = settings.collisions.dynamicFriction = 0.3;
  settings.substeps = 2;
  PbdSimulation sim(cloth, settings);
  const ObstacleSurface sphere = test::sphereObstacle(Vec3::Zero(), 0.3);
  sim.setObstacles({ sphere }, 0.0);
  std::size_t sphereCrossings = 0, selfCrossings = 0;
  double deepest = 1.0;
  for (int frame = 1; frame <= 32; ++frame)
  {
    sim.advance(frame * 0.025);
    const auto& x = sim.positions();
    sphereCrossings += test::crossingTriangles(cloth.surfaceTriangles, x, sphere.triangles, sphere.vertices, false);
    selfCrossings += test::crossingTriangles(cloth.surfaceTriangles, x, cloth.surfaceTriangles, x, true);
    for (const Vec3& p : x)
    {
      deepest = std::min(deepest, p.norm());
    }
  }
  // The sphere's facets lie within 0.3 cos(pi / 12) of its centre at worst.
  std::printf("closest cloth point to the sphere's centre %.4f m; crossings %zu (sphere), %zu (self)\n",
    deepest, sphereCrossings, selfCrossings);
  EXPECT_EQ(sphereCrossings, 0u);
  EXPECT_EQ(selfCrossings, 0u);
  EXPECT_GT(deepest, 0.3 * std::cos(M_PI / 12));
  EXPECT_LT(centroid(sim.positions()).z(), 0.3); // it fell and drapes over the sphere
}

TEST(PbdCollisions, BarFoldedOntoItselfDoesNotCrossItself)
{
  // A soft bar bent into a hairpin: the upper arm falls onto the lower one, which lies on
  // the floor. Self-collision keeps the arms apart: no surface triangle crosses another.
  const double R = 0.06, T = 0.04, arm = 0.3;
  const int along = 24;
  TetMesh mesh = makeTetBox(along, 1, 2, 1.0, Vec3::Zero());
  const double length = 2 * arm + M_PI * R - 0.06; // the upper arm ends short of the lower one
  for (Vec3& p : mesh.points)
  {
    const double s = p.x() / along * length, y = p.y() * 0.04, t = (p.z() / 2.0 - 0.5) * T;
    Vec3 c, n;
    if (s < arm)
    {
      c = Vec3(arm - s, 0, -R), n = Vec3(0, 0, -1);
    }
    else if (s < arm + M_PI * R)
    {
      const double phi = (s - arm) / R;
      c = Vec3(-R * std::sin(phi), 0, -R * std::cos(phi)), n = Vec3(-std::sin(phi), 0, -std::cos(phi));
    }
    else
    {
      c = Vec3(s - arm - M_PI * R, 0, R), n = Vec3(0, 0, 1);
    }
    // The bar narrows from 8 cm to 2 cm around the bend, so the upper arm lands well inside
    // the lower one's top face: its vertices meet faces. (Edges meeting edges, as equal widths
    // make them at the long sides, are not detected: contacts are vertex-triangle.)
    const double width = 0.08 - 0.06 * std::clamp((s - arm) / (M_PI * R), 0.0, 1.0);
    p = c + t * n + Vec3(0, (y / 0.04 - 0.5) * width, 0) + Vec3(0, 0, R + T / 2 + 0.002);
  }
  Body bar;
  bar.mesh.points = mesh.points;
  bar.mesh.tets = mesh.tets;
  bar.material.physical.youngsModulus = 2e5;
  PbdSettings settings = contactSettings(0.002);
  settings.formulation = PbdFormulation::Xpbd;
  settings.elasticFromMaterial = true;
  settings.floorEnabled = true;
  settings.collisions.mode = CollisionMode::ObstaclesBodiesAndSelf;
  settings.collisions.staticFriction = settings.collisions.dynamicFriction = 0.5;
  settings.substeps = 2;
  PbdSimulation sim(bar, settings);
  const auto surface = boundaryTriangles(sim.volumes().tets);
  std::size_t crossings = 0, selfContacts = 0;
  for (int frame = 1; frame <= 40; ++frame)
  {
    sim.advance(frame * 0.025);
    crossings += test::crossingTriangles(surface, sim.positions(), surface, sim.positions(), true);
    for (const Contact& c : sim.contacts())
    {
      selfContacts += c.kind == ContactKind::PointTriangle ? 1 : 0;
    }
  }
  // The outer half of the upper arm came down 8 cm onto the lower arm and rests on it.
  const double centre = R + T / 2 + 0.002;
  double upperBottom = 1.0, lowerTop = -1.0;
  for (std::size_t i = 0; i < bar.mesh.points.size(); ++i)
  {
    if (bar.mesh.points[i].x() > 0.1)
    {
      const double z = sim.positions()[i].z();
      (bar.mesh.points[i].z() > centre ? upperBottom : lowerTop) =
        bar.mesh.points[i].z() > centre ? std::min(upperBottom, z) : std::max(lowerTop, z);
    }
  }
  std::printf("self contacts %zu, crossings %zu, gap between the arms %.4f m (at rest %.3f m)\n",
    selfContacts, crossings, upperBottom - lowerTop, 2 * R - T);
  EXPECT_GT(selfContacts, 0u);
  EXPECT_EQ(crossings, 0u);
  EXPECT_GT(upperBottom - lowerTop, -settings.collisions.margin);
  EXPECT_LT(upperBottom - lowerTop, 0.01);
}

std::vector<Vec3> stackedRun(int threads)
{
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  PbdSettings settings = contactSettings();
  settings.floorEnabled = true;
  settings.particleRadius = 0.02;
  settings.collisions.mode = CollisionMode::ObstaclesBodiesAndSelf;
  settings.collisions.staticFriction = settings.collisions.dynamicFriction = 0.4;
  settings.collisions.restitution = 0.3;
  settings.solver = PbdSolver::ParallelGaussSeidel;
  Body scene = test::pbdBoxBody(3, 0.1, Vec3(-0.15, -0.15, 0.05));
  scene.pointMass.assign(scene.mesh.points.size(), 0.5);
  Body block = test::particleBlock(4, 0.04, Vec3(-0.02, -0.05, 0.45), 0.5);
  test::appendBody(scene, block);
  auto sim = makePbdSimulation(scene, settings);
  sim->setObstacles({ test::sphereObstacle(Vec3(0.3, 0, 0.1), 0.1) }, 0.0);
  sim->advance(0.3);
  std::vector<Vec3> out = sim->positions();
  out.insert(out.end(), sim->velocities().begin(), sim->velocities().end());
  return out;
}

TEST(PbdCollisions, ContactsGiveTheSameResultAtAnyThreadCount)
{
  const std::vector<Vec3> one = stackedRun(1), two = stackedRun(2);
  EXPECT_TRUE(test::bitwiseEqual(one, two)) << test::maxDistance(one, two);
}

} // namespace
} // namespace softbody
