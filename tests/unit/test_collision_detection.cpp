// Collision detection on the brute-force path: the closest-feature kernel against an
// independent construction, the boundary of tet meshes, and the detector's contacts against
// scenes whose answer is known (floor, obstacles, moving obstacles, tunnelling, particles,
// bodies against bodies, self-contact and its rest filter).
#include "collision_test_scenes.h"
#include "softbody/collision/closest_point.h"
#include "softbody/collision/contact_terms.h"
#include "softbody/common/errors.h"
#include "softbody/mesh/mesh_generators.h"
#include "test_support.h"

#include <tbb/global_control.h>

#include <gtest/gtest.h>

#include <map>
#include <random>

using namespace softbody;
using namespace softbody::test;

namespace
{

/// The closest point of a triangle built another way: the projection onto the plane when it
/// falls inside (all barycentric weights >= 0), else the nearest of the three segments.
Vec3 referenceClosest(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c)
{
  const Vec3 n = (b - a).cross(c - a).normalized();
  const Vec3 q = p - n.dot(p - a) * n;
  const double area = (b - a).cross(c - a).dot(n);
  const double wa = (b - q).cross(c - q).dot(n) / area;
  const double wb = (c - q).cross(a - q).dot(n) / area;
  const double wc = 1.0 - wa - wb;
  if (wa >= 0 && wb >= 0 && wc >= 0)
  {
    return q;
  }
  Vec3 best = a;
  for (auto [s, e] : { std::pair{ a, b }, std::pair{ b, c }, std::pair{ c, a } })
  {
    const Vec3 onSegment = s + closestPointOnSegment(p, s, e) * (e - s);
    if ((onSegment - p).norm() < (best - p).norm())
    {
      best = onSegment;
    }
  }
  return best;
}

CollisionSettings settingsWith(CollisionMode mode, double margin)
{
  CollisionSettings s;
  s.mode = mode;
  s.margin = margin;
  s.broadPhase = BroadPhase::BruteForce;
  return s;
}

/// One colliding point (a surface vertex, radius 0) with nothing else: for obstacle tests.
CollisionGeometry onePoint(const Vec3& rest, double radius = 0.0)
{
  CollisionGeometry g;
  addParticleBody(g, { rest }, radius, 0);
  return g;
}

ContactSet detectOnce(CollisionDetector& detector, const std::vector<Vec3>& start,
  const std::vector<Vec3>& predicted, double time = 0.0, double h = 0.01)
{
  ContactSet contacts;
  detector.detect(start, predicted, time, h, contacts);
  return contacts;
}

} // namespace

TEST(ClosestPoint, MatchesProjectionOrNearestEdgeOnRandomTriangles)
{
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int faces = 0, edges = 0, vertices = 0;
  for (int trial = 0; trial < 20000; ++trial)
  {
    const Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
    const Vec3 p = 2.0 * Vec3(u(rng), u(rng), u(rng));
    const TrianglePoint result = closestPointOnTriangle(p, a, b, c);
    const Vec3 expected = referenceClosest(p, a, b, c);
    ASSERT_NEAR((result.point - p).norm(), (expected - p).norm(), 1e-9) << "trial " << trial;
    ASSERT_LT((result.point - expected).norm(), 1e-6) << "trial " << trial;
    ASSERT_NEAR(result.barycentric.sum(), 1.0, 1e-12);
    ASSERT_GE(result.barycentric.minCoeff(), 0.0);
    ASSERT_LT((result.barycentric[0] * a + result.barycentric[1] * b + result.barycentric[2] * c - result.point).norm(), 1e-12);
    // The feature agrees with the weights: zero weights are exactly the vertices left out.
    const auto zeros = (result.barycentric.array() == 0.0).count();
    switch (result.feature)
    {
      case TriangleFeature::Face: EXPECT_EQ(zeros, 0); ++faces; break;
      case TriangleFeature::EdgeAB: EXPECT_EQ(result.barycentric[2], 0.0); ++edges; break;
      case TriangleFeature::EdgeBC: EXPECT_EQ(result.barycentric[0], 0.0); ++edges; break;
      case TriangleFeature::EdgeCA: EXPECT_EQ(result.barycentric[1], 0.0); ++edges; break;
      default: EXPECT_EQ(zeros, 2); ++vertices; break;
    }
  }
  // Each kind of region was reached often enough to mean something.
  EXPECT_GT(faces, 500);
  EXPECT_GT(edges, 500);
  EXPECT_GT(vertices, 500);
}

TEST(ClosestPoint, DegenerateTriangleGivesNearestEdgePoint)
{
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(2, 0, 0); // collinear
  const TrianglePoint result = closestPointOnTriangle(Vec3(1.5, 1, 0), a, b, c);
  EXPECT_TRUE(result.point.allFinite());
  EXPECT_NEAR((result.point - Vec3(1.5, 0, 0)).norm(), 0.0, 1e-12);
  const TrianglePoint point = closestPointOnTriangle(Vec3(0, 0, 1), a, a, a); // a point
  EXPECT_EQ(point.point, a);
}

TEST(BoundaryTriangles, BoxSurfaceIsClosedOutwardAndEnclosesItsVolume)
{
  const int nx = 3, ny = 4, nz = 2;
  const double h = 0.1;
  const TetMesh mesh = makeTetBox(nx, ny, nz, h, Vec3(0.3, -0.2, 0.1));
  const auto triangles = boundaryTriangles(mesh.tets);
  // Two triangles per boundary cell face.
  EXPECT_EQ(triangles.size(), static_cast<std::size_t>(4 * (nx * ny + ny * nz + nz * nx)));
  // Closed and consistently wound: every directed edge once, and its reverse once.
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : triangles)
  {
    for (int k = 0; k < 3; ++k)
    {
      ++directed[{ t[k], t[(k + 1) % 3] }];
    }
  }
  for (const auto& [edge, count] : directed)
  {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(directed.count({ edge.second, edge.first }), 1u);
  }
  // Outward: the divergence theorem, V = (1/3) sum over faces of centroid . area vector,
  // is the box's volume (it would be minus that with every face inward).
  double volume = 0.0;
  for (const auto& t : triangles)
  {
    const Vec3 &a = mesh.points[t[0]], &b = mesh.points[t[1]], &c = mesh.points[t[2]];
    volume += ((a + b + c) / 3.0).dot(0.5 * (b - a).cross(c - a)) / 3.0;
  }
  EXPECT_NEAR(volume, nx * ny * nz * h * h * h, 1e-12);
}

TEST(BoundaryTriangles, SingleTetFacesPointAwayFromTheOppositeVertex)
{
  const std::vector<Vec3> p{ Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1) };
  ASSERT_GT(signedTetVolume(p[0], p[1], p[2], p[3]), 0.0);
  const auto triangles = boundaryTriangles({ Tet{ 0, 1, 2, 3 } });
  ASSERT_EQ(triangles.size(), 4u);
  for (const auto& t : triangles)
  {
    const int opposite = 6 - t[0] - t[1] - t[2];
    const Vec3 normal = (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]);
    EXPECT_LT(normal.dot(p[opposite] - p[t[0]]), 0.0);
  }
  // Two tets sharing a face: that face is interior, 6 remain.
  EXPECT_EQ(boundaryTriangles({ Tet{ 0, 1, 2, 3 }, Tet{ 1, 2, 3, 4 } }).size(), 6u);
}

TEST(CollisionDetection, FloorContactIsTheProjectionWithinTheQueryRadius)
{
  FloorPlane floor;
  floor.origin = Vec3(0, 0, 1);
  floor.normal = Vec3(0, 1, 1); // normalized by the detector
  const double margin = 0.01;
  CollisionDetector detector(onePoint(Vec3(0, 0, 2)), settingsWith(CollisionMode::Obstacles, margin), true, floor);
  const Vec3 n = Vec3(0, 1, 1).normalized();
  const Vec3 near = floor.origin + Vec3(0.3, 0.2, -0.2) + 0.008 * n;
  ContactSet contacts = detectOnce(detector, { near }, { near });
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_EQ(contacts[0].kind, ContactKind::Obstacle);
  EXPECT_EQ(contacts[0].source, -1);
  EXPECT_NEAR((contacts[0].normal - n).norm(), 0.0, 1e-15);
  EXPECT_NEAR((contacts[0].surfacePoint - (near - 0.008 * n)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(n.dot(contacts[0].surfacePoint - floor.origin), 0.0, 1e-12);
  EXPECT_EQ(contacts[0].thickness, margin);
  // The floor's reach: the thickness plus three margins (inactive contacts that hold the
  // points the solve pushes down further than they moved) plus the substep's motion. Out of
  // reach at rest; in reach when the point moved there during the substep (swept).
  const Vec3 inReach = floor.origin + 0.039 * n;
  EXPECT_EQ(detectOnce(detector, { inReach }, { inReach }).size(), 1u);
  const Vec3 far = floor.origin + 0.041 * n;
  EXPECT_TRUE(detectOnce(detector, { far }, { far }).empty());
  EXPECT_EQ(detectOnce(detector, { far + 0.02 * n }, { far }).size(), 1u);
  // Far below the floor: still a contact (the floor is a half-space).
  EXPECT_EQ(detectOnce(detector, { floor.origin - n }, { floor.origin - n }).size(), 1u);
  // Mode Off detects nothing.
  CollisionDetector off(onePoint(Vec3(0, 0, 2)), settingsWith(CollisionMode::Off, margin), true, floor);
  EXPECT_TRUE(detectOnce(off, { floor.origin - n }, { floor.origin - n }).empty());
}

TEST(CollisionDetection, FloorAloneGivesTheContactsOfTheFullSearch)
{
  // With nothing but the floor to meet, detection takes a one-pass path (no neighbour search);
  // the same points and floor with body collisions on (one body, no self collision: nothing
  // more to find) take the full search. Both must give the same contacts, field by field.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  std::vector<Vec3> start, predicted;
  for (int i = 0; i < 2000; ++i)
  {
    start.emplace_back(u(rng), u(rng), 0.06 + u(rng)); // from 1 cm above the floor to 11 cm
    predicted.push_back(start.back() + Vec3(u(rng), u(rng), u(rng)) * 0.2);
  }
  CollisionGeometry g;
  addParticleBody(g, start, 0.002, 0);
  FloorPlane floor;
  floor.origin = Vec3(0, 0, 0.01);
  floor.normal = Vec3(0.1, 0.0, 1.0);
  CollisionDetector floorOnly(g, settingsWith(CollisionMode::Obstacles, 0.003), true, floor);
  CollisionDetector fullSearch(g, settingsWith(CollisionMode::ObstaclesAndBodies, 0.003), true, floor);
  const ContactSet a = detectOnce(floorOnly, start, predicted);
  const ContactSet b = detectOnce(fullSearch, start, predicted);
  ASSERT_GT(a.size(), 100u);
  ASSERT_LT(a.size(), start.size()); // some points are out of reach
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k)
  {
    EXPECT_EQ(a[k].point, b[k].point);
    EXPECT_EQ(a[k].kind, ContactKind::Obstacle);
    EXPECT_EQ(b[k].kind, ContactKind::Obstacle);
    EXPECT_EQ(a[k].source, b[k].source);
    EXPECT_EQ(a[k].normal, b[k].normal);
    EXPECT_EQ(a[k].surfacePoint, b[k].surfacePoint);
    EXPECT_EQ(a[k].thickness, b[k].thickness);
  }
  EXPECT_EQ(floorOnly.stats().candidatePairs, start.size()); // one floor test per point
}

TEST(CollisionDetection, ObstacleIsOneSidedWithTheClosestFeature)
{
  const double margin = 0.01, radius = 0.005;
  CollisionDetector detector(onePoint(Vec3(0, 0, 1), radius), settingsWith(CollisionMode::Obstacles, margin), false, {});
  detector.setObstacles({ flatObstacle(0.0, 1.0) }, 0.0);
  const double thickness = margin + radius;
  // In front, over the face: normal +z, surface point below it, thickness radius + margin.
  const Vec3 front(0.2, 0.1, 0.012);
  ContactSet contacts = detectOnce(detector, { front }, { front });
  ASSERT_EQ(contacts.size(), 1u) << "one contact, not one per triangle";
  EXPECT_EQ(contacts[0].source, 0);
  EXPECT_EQ(contacts[0].normal, Vec3::UnitZ());
  EXPECT_NEAR((contacts[0].surfacePoint - Vec3(0.2, 0.1, 0)).norm(), 0.0, 1e-15);
  EXPECT_EQ(contacts[0].thickness, thickness);
  EXPECT_NEAR(contacts[0].barycentric.sum(), 1.0, 1e-15);
  // Beyond the edge, in front: the edge's direction, not the face normal.
  const Vec3 beyond(1.0 + 0.006, 0.0, 0.008);
  contacts = detectOnce(detector, { beyond }, { beyond });
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_NEAR((contacts[0].normal - Vec3(0.6, 0, 0.8)).norm(), 0.0, 1e-12);
  // Just behind (penetrated less than the query radius): pushed out the front.
  const Vec3 behind(0.2, 0.1, -0.5 * thickness);
  contacts = detectOnce(detector, { behind }, { behind });
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_EQ(contacts[0].normal, Vec3::UnitZ());
  // Deeper behind than the query radius: the other side of the surface, no contact.
  const Vec3 deep(0.2, 0.1, -2.0 * thickness);
  EXPECT_TRUE(detectOnce(detector, { deep }, { deep }).empty());
  // Behind and beyond the edge: no contact (the back of an open surface).
  const Vec3 behindEdge(1.006, 0.0, -0.004);
  EXPECT_TRUE(detectOnce(detector, { behindEdge }, { behindEdge }).empty());
}

TEST(CollisionDetection, FastPointCrossingAThinObstacleIsCaughtOnItsFrontSide)
{
  CollisionDetector detector(onePoint(Vec3(0, 0, 1)), settingsWith(CollisionMode::Obstacles, 0.001), false, {});
  detector.setObstacles({ flatObstacle(0.0, 1.0) }, 0.0);
  // 1 m in one substep (100 m/s at h = 0.01 s): from 0.5 m above to 0.5 m below the plane.
  const ContactSet contacts = detectOnce(detector, { Vec3(0.1, 0.1, 0.5) }, { Vec3(0.1, 0.1, -0.5) });
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_EQ(contacts[0].normal, Vec3::UnitZ());
  EXPECT_LT(contacts[0].normal.dot(Vec3(0.1, 0.1, -0.5) - contacts[0].surfacePoint) - contacts[0].thickness, 0.0)
    << "the constraint is violated, so the response will push the point back to the front";
}

TEST(CollisionDetection, ClosedObstacleGivesOneContactPerFeatureAndBothFacesOfACorner)
{
  const double margin = 0.02;
  CollisionDetector detector(onePoint(Vec3(5, 5, 5)), settingsWith(CollisionMode::Obstacles, margin), false, {});
  detector.setObstacles({ boxObstacle(Vec3(0, 0, 0), Vec3(1, 1, 1)) }, 0.0);
  // Next to a convex edge (x = 1, z = 1), outside: one contact, along the diagonal.
  const Vec3 edge = Vec3(1, 0.5, 1) + 0.01 * Vec3(1, 0, 1).normalized();
  ContactSet contacts = detectOnce(detector, { edge }, { edge });
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_NEAR((contacts[0].normal - Vec3(1, 0, 1).normalized()).norm(), 0.0, 1e-12);
  // Next to a corner: one contact.
  const Vec3 corner = Vec3(1, 1, 1) + 0.01 * Vec3(1, 1, 1).normalized();
  EXPECT_EQ(detectOnce(detector, { corner }, { corner }).size(), 1u);
  // Just inside, near the top face's middle: pushed up through that face only.
  const Vec3 inside(0.5, 0.5, 0.99);
  contacts = detectOnce(detector, { inside }, { inside });
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_EQ(contacts[0].normal, Vec3::UnitZ());
  // A concave corner: the floor and a wall of an open bowl, the point near both.
  ObstacleSurface bowl = flatObstacle(0.0, 1.0);
  const auto base = static_cast<std::int32_t>(bowl.vertices.size());
  bowl.vertices.insert(bowl.vertices.end(), { Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(1, 1, 1), Vec3(1, -1, 1) });
  bowl.triangles.push_back({ base + 0, base + 2, base + 1 }); // the wall x = 1, normal -x
  bowl.triangles.push_back({ base + 0, base + 3, base + 2 });
  detector.setObstacles({ bowl }, 0.0);
  const Vec3 nook(0.99, 0.1, 0.01);
  contacts = detectOnce(detector, { nook }, { nook });
  ASSERT_EQ(contacts.size(), 2u);
  EXPECT_EQ(contacts[0].normal.dot(contacts[1].normal), 0.0);
}

TEST(CollisionDetection, PointBetweenTwoPartsOfOneObstacleTouchesBoth)
{
  // Two boxes in one obstacle surface, 0.02 apart along x, the right one taller; a point in
  // the gap above the left box's top edge, nearer to the right box's face than to that edge.
  // Both must push it: the edge is not covered by a face of another part.
  ObstacleSurface twoBoxes = boxObstacle(Vec3(0, 0, 0), Vec3(1, 1, 1));
  const ObstacleSurface right = boxObstacle(Vec3(1.02, 0, 0), Vec3(2, 1, 2));
  const auto base = static_cast<std::int32_t>(twoBoxes.vertices.size());
  twoBoxes.vertices.insert(twoBoxes.vertices.end(), right.vertices.begin(), right.vertices.end());
  for (auto t : right.triangles)
  {
    twoBoxes.triangles.push_back({ t[0] + base, t[1] + base, t[2] + base });
  }
  CollisionDetector detector(onePoint(Vec3(5, 5, 5)), settingsWith(CollisionMode::Obstacles, 0.02), false, {});
  detector.setObstacles({ twoBoxes }, 0.0);
  const Vec3 gap(1.012, 0.5, 1.003); // 0.008 from the right face, 0.0124 from the left edge
  const ContactSet contacts = detectOnce(detector, { gap }, { gap });
  ASSERT_EQ(contacts.size(), 2u);
  int pushedLeft = 0, pushedRight = 0;
  for (const Contact& c : contacts)
  {
    pushedLeft += c.normal.x() < -0.99; // the right box's face x = 1.02
    pushedRight += c.normal.x() > 0.1;  // the left box's edge, diagonally
  }
  EXPECT_EQ(pushedLeft, 1);
  EXPECT_EQ(pushedRight, 1);
}

TEST(CollisionDetection, RidgeNearerThanTheFloorItStandsOnIsKept)
{
  // A floor square and a thin wall standing on its edge (sharing its vertices): a point above
  // the floor near the wall's top ridge touches the ridge and, within the margin, the floor.
  ObstacleSurface floorAndWall = flatObstacle(0.0, 1.0); // vertices 0..3, edge 1-2 at x = 1
  floorAndWall.vertices.push_back(Vec3(1, -1, 0.05));
  floorAndWall.vertices.push_back(Vec3(1, 1, 0.05));
  floorAndWall.triangles.push_back({ 1, 5, 2 }); // wall x = 1, normal -x (toward the floor)
  floorAndWall.triangles.push_back({ 1, 4, 5 });
  CollisionDetector detector(onePoint(Vec3(5, 5, 5)), settingsWith(CollisionMode::Obstacles, 0.06), false, {});
  detector.setObstacles({ floorAndWall }, 0.0);
  const Vec3 x(0.99, 0.0, 0.055); // 0.011 from the ridge, 0.055 above the floor
  const ContactSet contacts = detectOnce(detector, { x }, { x });
  ASSERT_EQ(contacts.size(), 2u);
  bool floorFound = false, ridgeFound = false;
  for (const Contact& c : contacts)
  {
    floorFound = floorFound || c.normal == Vec3::UnitZ();
    ridgeFound = ridgeFound || (c.normal.z() > 0.1 && c.normal.x() < -0.1);
  }
  EXPECT_TRUE(floorFound);
  EXPECT_TRUE(ridgeFound);
}

TEST(CollisionDetection, MovingObstacleIsWhereItsVelocityPutsItAndCarriesItsVelocity)
{
  const double margin = 0.01, endTime = 2.0, h = 0.01, time = 1.5;
  CollisionDetector detector(onePoint(Vec3(0, 0, 1)), settingsWith(CollisionMode::Obstacles, margin), false, {});
  // A plane rotating about the z axis while rising: v(x) = omega x (x) + (0, 0, 1) m/s, a
  // linear field that barycentric interpolation reproduces exactly.
  ObstacleSurface surface = flatObstacle(0.0, 1.0);
  const Vec3 omega(0, 0, 2.0), rise(0, 0, 1.0);
  for (const Vec3& v : surface.vertices)
  {
    surface.velocities.push_back(omega.cross(v) + rise);
  }
  detector.setObstacles({ surface }, endTime);
  // At the end of the substep, t = 1.51, the plane is at z = (1.51 - 2) * 1 = -0.49.
  const double planeZ = (time + h - endTime) * rise.z();
  const Vec3 x(0.3, -0.2, planeZ + 0.005);
  ContactSet contacts = detectOnce(detector, { x }, { x }, time, h);
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_NEAR(contacts[0].surfacePoint.z(), planeZ, 1e-12);
  // The closest point and its velocity are those of one material point of the plane: with
  // q = sum_k w_k vertices_k (where it is at endTime), it is at q + (t - endTime) v(q) and
  // moves with v(q) = omega x q + rise, the field being linear.
  const auto& t = surface.triangles[contacts[0].other[0]];
  Vec3 q = Vec3::Zero();
  for (int k = 0; k < 3; ++k)
  {
    q += contacts[0].barycentric[k] * surface.vertices[t[k]];
  }
  const Vec3 v = omega.cross(q) + rise;
  EXPECT_NEAR((contacts[0].surfaceVelocity - v).norm(), 0.0, 1e-12);
  EXPECT_NEAR((contacts[0].surfacePoint - (q + (time + h - endTime) * v)).norm(), 0.0, 1e-12);
  // The same point is out of reach of the plane where it stands at endTime (z = 0).
  EXPECT_TRUE(detectOnce(detector, { x }, { x }, endTime - h, h).empty());
}

TEST(CollisionDetection, ParticlesOfDifferentBodiesTouchAtTheirRadiiPlusTheMargin)
{
  CollisionGeometry g;
  const double r0 = 0.01, r1 = 0.02, margin = 0.002;
  addParticleBody(g, { Vec3(0, 0, 0) }, r0, 0);
  addParticleBody(g, { Vec3(0.1, 0, 0) }, r1, 1);
  CollisionDetector detector(g, settingsWith(CollisionMode::ObstaclesAndBodies, margin), false, {});
  const double reach = r0 + r1 + margin;
  const std::vector<Vec3> near{ Vec3(0, 0, 0), Vec3(0.99 * reach, 0, 0) };
  ContactSet contacts = detectOnce(detector, near, near);
  ASSERT_EQ(contacts.size(), 1u) << "one contact per pair";
  EXPECT_EQ(contacts[0].kind, ContactKind::PointPoint);
  EXPECT_EQ(contacts[0].point, 0);
  EXPECT_EQ(contacts[0].other[0], 1);
  EXPECT_EQ(contacts[0].source, 1);
  EXPECT_EQ(contacts[0].thickness, reach);
  EXPECT_EQ(contacts[0].normal, Vec3(-1, 0, 0)) << "from the other particle toward the point";
  const std::vector<Vec3> far{ Vec3(0, 0, 0), Vec3(1.01 * reach, 0, 0) };
  EXPECT_TRUE(detectOnce(detector, far, far).empty());
  // Swept: the second particle came from further away and passed through during the substep.
  EXPECT_EQ(detectOnce(detector, { Vec3(0, 0, 0), Vec3(0.1, 0, 0) }, { Vec3(0, 0, 0), Vec3(-0.05, 0, 0) }).size(), 1u);
  // Obstacles only: bodies do not see each other.
  CollisionDetector obstaclesOnly(g, settingsWith(CollisionMode::Obstacles, margin), false, {});
  EXPECT_TRUE(detectOnce(obstaclesOnly, near, near).empty());
}

TEST(CollisionDetection, ParticleSelfContactSkipsRestNeighbours)
{
  // A row of 10 particles 2 r apart (touching at rest), bent so that its ends meet.
  CollisionGeometry g;
  const double r = 0.01;
  std::vector<Vec3> row;
  for (int i = 0; i < 10; ++i)
  {
    row.emplace_back(2 * r * i, 0, 0);
  }
  addParticleBody(g, row, r, 0);
  CollisionDetector self(g, settingsWith(CollisionMode::ObstaclesBodiesAndSelf, 0.0), false, {});
  EXPECT_TRUE(detectOnce(self, row, row).empty()) << "neighbours at rest are not contacts";
  std::vector<Vec3> bent = row;
  bent[9] = bent[0] + Vec3(0, 2 * r, 0); // the last one folded back onto the first
  ContactSet contacts = detectOnce(self, bent, bent);
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_EQ(contacts[0].point, 0);
  EXPECT_EQ(contacts[0].other[0], 9);
  EXPECT_EQ(contacts[0].source, 0);
  CollisionDetector bodies(g, settingsWith(CollisionMode::ObstaclesAndBodies, 0.0), false, {});
  EXPECT_TRUE(detectOnce(bodies, bent, bent).empty()) << "self contacts only in the Self mode";
}

TEST(CollisionDetection, StackedTetBodiesTouchThroughSurfaceVerticesAndTriangles)
{
  const double h = 0.1, margin = 0.01;
  CollisionGeometry g;
  addTetBody(g, makeTetBox(2, 2, 1, h, Vec3(0, 0, 0)), 0);
  const TetMesh top = makeTetBox(2, 2, 1, h, Vec3(0.03, 0.04, 0.0));
  addTetBody(g, top, 1);
  const std::size_t bottomCount = g.rest.size() - top.points.size();
  // The top box rests 0.005 above the bottom one's top face (z = 0.1).
  std::vector<Vec3> x = g.rest;
  for (std::size_t i = bottomCount; i < x.size(); ++i)
  {
    x[i].z() += h + 0.005;
  }
  CollisionDetector detector(g, settingsWith(CollisionMode::ObstaclesAndBodies, margin), false, {});
  const ContactSet contacts = detectOnce(detector, x, x);
  ASSERT_FALSE(contacts.empty());
  std::size_t down = 0, up = 0, edges = 0;
  for (const Contact& c : contacts)
  {
    EXPECT_NE(c.source, g.bodyOf[c.point]) << "bodies only, no self contact";
    EXPECT_EQ(c.source, g.bodyOf[c.other[c.kind == ContactKind::EdgeEdge ? 1 : 0]]);
    // The contact's constraint value is the real gap minus the thickness: 0.005 - margin.
    const ContactTerms terms = termsOf(c);
    Vec3 r = Vec3::Zero();
    for (int j = 0; j < terms.count; ++j)
    {
      r += terms.coefficient[j] * x[terms.index[j]];
    }
    const double gap = c.normal.dot(r);
    if (c.kind == ContactKind::EdgeEdge)
    {
      // The edges of the top box's bottom face crossing those of the bottom box's top face,
      // a face apart: their common perpendicular is vertical.
      ++edges;
      EXPECT_NEAR(std::abs(c.normal.z()), 1.0, 1e-12);
      EXPECT_NEAR(gap, 0.005, 1e-12);
      continue;
    }
    EXPECT_EQ(c.kind, ContactKind::PointTriangle);
    EXPECT_NEAR(c.barycentric.sum(), 1.0, 1e-12);
    if (c.normal.z() > 0.99)
    {
      ++up;
      EXPECT_NEAR(gap, 0.005, 1e-12);
    }
    else if (c.normal.z() < -0.99)
    {
      ++down;
      EXPECT_NEAR(gap, 0.005, 1e-12);
    }
  }
  EXPECT_GT(edges, 0u);
  // Top-box bottom vertices over the bottom box's top face, and the reverse.
  EXPECT_GT(up, 0u);
  EXPECT_GT(down, 0u);
  // Sorted by (point, kind, source, other).
  for (std::size_t i = 1; i < contacts.size(); ++i)
  {
    EXPECT_LE(contacts[i - 1].point, contacts[i].point);
  }
}

TEST(CollisionDetection, FoldedBarTouchesItselfButNotAtRest)
{
  // A bar 10 cells long; its far end is brought under its near end (a fold).
  const double h = 0.05;
  CollisionGeometry g;
  const TetMesh bar = makeTetBox(10, 1, 1, h);
  addTetBody(g, bar, 0);
  CollisionDetector self(g, settingsWith(CollisionMode::ObstaclesBodiesAndSelf, 0.0), false, {});
  EXPECT_NEAR(self.margin(), 0.1 * [&] {
    double sum = 0;
    for (const auto& t : g.surfaceTriangles)
      for (int k = 0; k < 3; ++k) sum += (g.rest[t[(k + 1) % 3]] - g.rest[t[k]]).norm();
    return sum / (3.0 * static_cast<double>(g.surfaceTriangles.size()));
  }(), 1e-15) << "automatic margin: a tenth of the mean surface edge";
  EXPECT_TRUE(detectOnce(self, g.rest, g.rest).empty()) << "the rest filter leaves the body alone at rest";
  // Fold: points with x > 0.3 are mirrored to lie just below the bar (z -> -z - 0.2 margin).
  std::vector<Vec3> folded = g.rest;
  const double gap = 0.5 * self.margin();
  for (Vec3& p : folded)
  {
    if (p.x() > 0.3)
    {
      p = Vec3(0.6 - p.x(), p.y(), -gap - p.z() + 0.0);
    }
  }
  const ContactSet contacts = detectOnce(self, folded, folded);
  ASSERT_FALSE(contacts.empty());
  for (const Contact& c : contacts)
  {
    EXPECT_TRUE(c.kind == ContactKind::PointTriangle || c.kind == ContactKind::EdgeEdge);
    EXPECT_EQ(c.source, 0);
    // Nothing against its own triangle, or an edge against one it shares a corner with.
    const ContactTerms terms = termsOf(c);
    const int sideOne = c.kind == ContactKind::EdgeEdge ? 2 : 1;
    for (int j = 0; j < sideOne; ++j)
    {
      for (int k = sideOne; k < terms.count; ++k)
      {
        EXPECT_NE(terms.index[j], terms.index[k]);
      }
    }
  }
  CollisionDetector bodies(g, settingsWith(CollisionMode::ObstaclesAndBodies, 0.0), false, {});
  EXPECT_TRUE(detectOnce(bodies, folded, folded).empty());
}

TEST(CollisionDetection, TwoSidedTriangleKeepsThePointOnTheSideItStarted)
{
  // A cloth-like square (two triangles, two-sided) as body 0 and one vertex of body 1 below it.
  CollisionGeometry g;
  for (const Vec3& p : flatObstacle(0.0, 1.0).vertices)
  {
    g.rest.push_back(p);
    g.bodyOf.push_back(0);
    g.radius.push_back(0.0);
  }
  g.surfaceTriangles = { { 0, 1, 2 }, { 0, 2, 3 } };
  g.twoSided = { 1, 1 };
  addParticleBody(g, { Vec3(0.2, 0.1, -0.5) }, 0.0, 1);
  CollisionDetector detector(g, settingsWith(CollisionMode::ObstaclesAndBodies, 0.01), false, {});
  std::vector<Vec3> start = g.rest, predicted = g.rest;
  start[4] = Vec3(0.2, 0.1, -0.1);
  predicted[4] = Vec3(0.2, 0.1, 0.05); // crossed upward during the substep
  const ContactSet contacts = detectOnce(detector, start, predicted);
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_EQ(contacts[0].normal, -Vec3::UnitZ()) << "pushed back down, where it came from";
  g.twoSided.clear(); // one-sided: +z is the free side, so the point that crossed stays above
  CollisionDetector oneSided(g, settingsWith(CollisionMode::ObstaclesAndBodies, 0.01), false, {});
  const ContactSet above = detectOnce(oneSided, start, predicted);
  ASSERT_EQ(above.size(), 1u);
  EXPECT_EQ(above[0].normal, Vec3::UnitZ());
}

TEST(CollisionDetection, SameContactsAtOneAndTwoThreads)
{
  CollisionGeometry g;
  addTetBody(g, makeTetBox(6, 6, 3, 0.05), 0);
  addTetBody(g, makeTetBox(6, 6, 3, 0.05, Vec3(0.1, 0.05, 0.16)), 1);
  std::vector<Vec3> centres;
  for (int i = 0; i < 300; ++i)
  {
    centres.push_back(Vec3(0.01 * (i % 30), 0.02 * (i / 30), 0.32));
  }
  addParticleBody(g, centres, 0.006, 2);
  const std::vector<Vec3> start = jitter(g.rest, 0.01, 5);
  const std::vector<Vec3> predicted = jitter(start, 0.01, 6);
  FloorPlane floor;
  floor.origin = Vec3(0, 0, 0.01);
  auto run = [&](std::size_t threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    CollisionDetector detector(g, settingsWith(CollisionMode::ObstaclesBodiesAndSelf, 0.01), true, floor);
    detector.setObstacles({ boxObstacle(Vec3(0.1, 0.1, 0.3), Vec3(0.2, 0.2, 0.4)) }, 0.0);
    return detectOnce(detector, start, predicted);
  };
  const ContactSet one = run(1), two = run(2);
  EXPECT_GT(one.size(), 100u);
  EXPECT_TRUE(sameContacts(one, two));
}

TEST(CollisionDetection, BadSettingsAndObstaclesAreRefusedQuotingTheValue)
{
  const CollisionGeometry g = onePoint(Vec3(0, 0, 0));
  CollisionSettings s;
  s.margin = -0.5;
  try
  {
    CollisionDetector(g, s, false, {});
    FAIL() << "a negative margin was accepted";
  }
  catch (const InvalidInputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("-0.5"), std::string::npos) << e.what();
  }
  s = {};
  s.restitution = 1.5;
  EXPECT_THROW(CollisionDetector(g, s, false, {}), InvalidInputError);
  s = {};
  s.staticFriction = -1;
  EXPECT_THROW(CollisionDetector(g, s, false, {}), InvalidInputError);
  CollisionDetector detector(g, {}, false, {});
  ObstacleSurface bad = flatObstacle(0, 1);
  bad.triangles.push_back({ 0, 1, 7 });
  try
  {
    detector.setObstacles({ bad }, 0.0);
    FAIL() << "an out-of-range index was accepted";
  }
  catch (const InvalidInputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("7"), std::string::npos) << e.what();
  }
  bad = flatObstacle(0, 1);
  bad.velocities.resize(2, Vec3::Zero());
  EXPECT_THROW(detector.setObstacles({ bad }, 0.0), InvalidInputError);
  CollisionGeometry inconsistent = g;
  inconsistent.radius.push_back(0.1);
  EXPECT_THROW(CollisionDetector(inconsistent, {}, false, {}), InvalidInputError);
}
