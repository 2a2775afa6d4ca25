// The PBD/XPBD contact kernels on hand-made contacts: the inequality restored exactly, shared by
// inverse mass and barycentric weight with momentum kept, Coulomb's static and dynamic friction
// at the position level (relative to a moving surface), restitution; a tet crushed on the floor
// raised back to its least volume without moving into it.
#include "softbody/pbd/pbd_contact_kernels.h"

#include <gtest/gtest.h>

namespace softbody
{
namespace
{
Contact floorContact(double thickness = 0.0)
{
  Contact c;
  c.kind = ContactKind::Obstacle;
  c.point = 0;
  c.normal = Vec3::UnitZ();
  c.surfacePoint = Vec3::Zero();
  c.thickness = thickness;
  return c;
}

TEST(PbdContactKernels, ObstacleContactRestoresTheThicknessOnlyWhenViolated)
{
  const Contact contact = floorContact(0.01);
  ContactMultipliers lambda;
  const Vec3 below(0.3, -0.2, -0.05);
  const Projection<1> p = projectObstacleContact(below, below, 2.0, contact, 1e-2, {}, lambda);
  EXPECT_NEAR((below + p.dx[0]).z(), 0.01, 1e-15);
  EXPECT_EQ((below + p.dx[0]).head<2>(), below.head<2>()); // frictionless: straight out
  EXPECT_NEAR(lambda.normal, 0.06 / 2.0, 1e-15);           // -C / w
  ContactMultipliers untouched;
  const Vec3 above(0, 0, 0.02);
  const Projection<1> q = projectObstacleContact(above, above, 2.0, contact, 1e-2, {}, untouched);
  EXPECT_EQ(q.dx[0], Vec3::Zero()); // an inequality never pulls
  EXPECT_EQ(untouched.normal, 0.0);
  ContactMultipliers pinned;
  EXPECT_EQ(projectObstacleContact(below, below, 0.0, contact, 1e-2, {}, pinned).dx[0], Vec3::Zero());
}

TEST(PbdContactKernels, PointTriangleContactKeepsMomentumAndRestoresTheThickness)
{
  // A point 0.02 below a triangle's plane (normal +z toward the point's free side, so it
  // penetrates), hitting it at barycentric (0.2, 0.3, 0.5).
  Contact contact;
  contact.kind = ContactKind::PointTriangle;
  contact.barycentric = Vec3(0.2, 0.3, 0.5);
  contact.normal = Vec3::UnitZ();
  contact.thickness = 0.005;
  const std::array<Vec3, 4> x{ Vec3(0.32, 0.45, -0.02), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0) };
  const std::array<double, 4> w{ 1.0, 2.0, 0.5, 3.0 };
  ContactMultipliers lambda;
  const Projection<4> p = projectSurfaceContact(x, x, w, contact, {}, lambda);
  std::array<Vec3, 4> y;
  Vec3 momentum = Vec3::Zero();
  for (int k = 0; k < 4; ++k)
  {
    y[k] = x[k] + p.dx[k];
    momentum += p.dx[k] / w[k];
  }
  const Vec3& b = contact.barycentric;
  const double C = contact.normal.dot(y[0] - b[0] * y[1] - b[1] * y[2] - b[2] * y[3]) - contact.thickness;
  EXPECT_NEAR(C, 0.0, 1e-15);
  EXPECT_LT(momentum.norm(), 1e-15); // sum of m dx = (1 - sum b) D = 0
  // The corners move by c_k w_k: opposite to the point, in proportion b_k w_k.
  EXPECT_NEAR(p.dx[3].z() / p.dx[1].z(), (0.5 * 3.0) / (0.2 * 2.0), 1e-12);
  EXPECT_LT(p.dx[1].z(), 0.0);
  EXPECT_GT(p.dx[0].z(), 0.0);

  // A pinned triangle leaves all the work to the point.
  ContactMultipliers again;
  const Projection<4> q = projectSurfaceContact(x, x, { 1.0, 0.0, 0.0, 0.0 }, contact, {}, again);
  EXPECT_NEAR((x[0] + q.dx[0]).z(), 0.005, 1e-15);
  EXPECT_EQ(q.dx[1], Vec3::Zero());
}

TEST(PbdContactKernels, PointPointContactSeparatesSpheresAlongTheirCentres)
{
  Contact contact;
  contact.kind = ContactKind::PointPoint;
  contact.thickness = 0.1; // two radii of 0.05
  const std::array<Vec3, 2> x{ Vec3(0.03, 0.04, 0), Vec3(0, 0, 0) };
  ContactMultipliers lambda;
  const Projection<2> p = projectPointPointContact(x, x, { 1.0, 3.0 }, contact, {}, lambda);
  const Vec3 a = x[0] + p.dx[0], b = x[1] + p.dx[1];
  EXPECT_NEAR((a - b).norm(), 0.1, 1e-15);
  EXPECT_LT((p.dx[0] / 1.0 + p.dx[1] / 3.0).norm(), 1e-16);
  EXPECT_LT((p.dx[0].normalized() - Vec3(0.6, 0.8, 0)).norm(), 1e-14); // along the centres
}

TEST(PbdContactKernels, StaticFrictionStopsSlipBelowTheCone)
{
  // A particle moved 1 mm sideways and 2 mm into the floor this substep: with mu_s = 0.6 the
  // cone allows 1.2 mm of correction, so the slip is removed entirely.
  const Contact contact = floorContact();
  const Vec3 start(0, 0, 0);
  const Vec3 x(0.001, 0, -0.002);
  ContactMultipliers lambda;
  const Projection<1> p = projectObstacleContact(x, start, 1.0, contact, 1e-2, { 0.6, 0.4 }, lambda);
  const Vec3 y = x + p.dx[0];
  EXPECT_NEAR(y.x(), 0.0, 1e-15);
  EXPECT_NEAR(y.z(), 0.0, 1e-15);
}

TEST(PbdContactKernels, DynamicFrictionReducesSlipByMuKTimesTheNormalCorrection)
{
  // Slip 5 mm, penetration 2 mm, mu_s = 0.6 (cone 1.2 mm): sliding, the slip shrinks by
  // mu_k * 2 mm = 0.8 mm, along the slip direction.
  const Contact contact = floorContact();
  const Vec3 start(0, 0, 0);
  const Vec3 x(0.003, 0.004, -0.002);
  ContactMultipliers lambda;
  const Projection<1> p = projectObstacleContact(x, start, 0.5, contact, 1e-2, { 0.6, 0.4 }, lambda);
  const Vec3 y = x + p.dx[0];
  EXPECT_NEAR(y.head<2>().norm(), 0.005 - 0.4 * 0.002, 1e-15);
  EXPECT_NEAR(y.x() / y.y(), 0.75, 1e-12);
  // A second iteration with no new penetration adds nothing: the cone is already reached.
  const Projection<1> q = projectObstacleContact(y, start, 0.5, contact, 1e-2, { 0.6, 0.4 }, lambda);
  EXPECT_LT(q.dx[0].norm(), 1e-18);
}

TEST(PbdContactKernels, FrictionActsOnTheSlipRelativeToAMovingSurface)
{
  // A conveyor moving at 1 m/s for 10 ms: a particle that moved with it does not slip; one
  // that stayed is dragged along (static friction: by the whole 1 cm if the cone allows it).
  Contact contact = floorContact();
  contact.surfaceVelocity = Vec3(1, 0, 0);
  const Vec3 start(0, 0, 0);
  ContactMultipliers carried;
  const Projection<1> p =
    projectObstacleContact(Vec3(0.01, 0, -0.001), start, 1.0, contact, 1e-2, { 1.0, 1.0 }, carried);
  EXPECT_NEAR(p.dx[0].x(), 0.0, 1e-15);
  ContactMultipliers left;
  const Projection<1> q =
    projectObstacleContact(Vec3(0, 0, -0.02), start, 1.0, contact, 1e-2, { 1.0, 1.0 }, left);
  EXPECT_NEAR(q.dx[0].x(), 0.01, 1e-15);
}

TEST(PbdContactKernels, RestitutionBouncesImpactsAndLeavesRestingContacts)
{
  EXPECT_DOUBLE_EQ(restitutionSpeedChange(-2.0, 0.0, 0.5, 0.1), 1.0);   // leaves at e v
  EXPECT_DOUBLE_EQ(restitutionSpeedChange(-2.0, 1.5, 0.5, 0.1), 0.0);   // already faster
  EXPECT_DOUBLE_EQ(restitutionSpeedChange(-0.05, 0.0, 0.5, 0.1), 0.0);  // resting
  EXPECT_DOUBLE_EQ(restitutionSpeedChange(1.0, -0.5, 0.5, 0.1), 0.0);   // separating
}


namespace heldtet
{
/// Corner k held by `contacts[k]` (null: not held).
std::array<HeldCorner, 4> corners(const std::array<const Contact*, 4>& contacts)
{
  std::array<HeldCorner, 4> held;
  for (int k = 0; k < 4; ++k)
  {
    if (contacts[k] != nullptr)
    {
      held[k] = { contacts[k], contacts[k] + 1 };
    }
  }
  return held;
}

/// Applies uncrushHeldTet `passes` times; checks that no corner ever moves down (into the floor).
double uncrush(std::array<Vec3, 4>& x, const std::array<double, 4>& w, double least,
  const std::array<HeldCorner, 4>& held, int passes)
{
  for (int pass = 0; pass < passes; ++pass)
  {
    const std::array<Vec3, 4> dx = uncrushHeldTet(x, w, least, held);
    for (int k = 0; k < 4; ++k)
    {
      EXPECT_GE(dx[k].z(), 0.0) << "corner " << k << " pushed into the floor at pass " << pass;
      x[k] += dx[k];
    }
  }
  return signedTetVolume(x[0], x[1], x[2], x[3]);
}
} // namespace heldtet

TEST(PbdContactKernels, HeldTetFlattenedOnTheFloorIsRaisedAwayFromIt)
{
  // A tet with all four corners held on the floor plane, nearly flat (V = 0.01 V0, as the
  // contacts leave a bottom tet): restored to the least volume by raising corners only, where
  // a plain volume projection would push half of them down into the floor.
  const std::array<Vec3, 4> rest = { Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.3, 0.3, 1) };
  const double restVolume = signedTetVolume(rest[0], rest[1], rest[2], rest[3]);
  const double least = kLeastVolumeFraction * restVolume;
  std::array<Vec3, 4> x = rest;
  x[3].z() = 0.01;
  const Contact floor = floorContact(0.0);
  const std::array<double, 4> w = { 1.0, 2.0, 0.5, 1.0 };
  const auto held = heldtet::corners({ &floor, &floor, &floor, &floor });
  const double after = heldtet::uncrush(x, w, least, held, 3);
  EXPECT_GE(after, least * (1.0 - 1e-12));
  EXPECT_LT(after, 1.01 * least); // to the limit, not beyond: it is an inequality
  for (int k = 0; k < 3; ++k)
  {
    EXPECT_EQ(x[k].z(), 0.0); // the base's gradients point down: masked away entirely
  }
  // The plain projection would have moved the base down: its gradient is -z.
  const Vec3 g0 = (x[3] - x[1]).cross(x[2] - x[1]);
  EXPECT_LT(g0.z(), 0.0);
}

TEST(PbdContactKernels, HeldTetTurnedInsideOutIsRestoredWithoutPushingAnyCornerDown)
{
  // Base held on the floor, its apex (not held: just above the floor, outside the contact
  // set) pushed through the base plane: V = -0.3 V0. The apex may move only up as well,
  // since only the floor holds the tet; a few passes (the volume is cubic) reach the limit.
  const std::array<Vec3, 4> rest = { Vec3(0, 0, 0.002), Vec3(1, 0, 0.002), Vec3(0, 1, 0.002), Vec3(0.2, 0.2, 1.002) };
  const double restVolume = signedTetVolume(rest[0], rest[1], rest[2], rest[3]);
  std::array<Vec3, 4> x = rest;
  x[3].z() = 0.002 - 0.3;
  Contact floor = floorContact(0.002);
  const auto held = heldtet::corners({ &floor, &floor, &floor, nullptr });
  const std::array<double, 4> w = { 1.0, 1.0, 1.0, 1.0 };
  const double least = kLeastVolumeFraction * restVolume;
  const double after = heldtet::uncrush(x, w, least, held, 4);
  EXPECT_GE(after, least * (1.0 - 1e-9));
  for (int k = 0; k < 3; ++k)
  {
    EXPECT_GE(x[k].z(), 0.002); // still on the free side of its contact
  }
}

TEST(PbdContactKernels, HeldTetAboveTheLeastVolumeOrPinnedIsLeftAlone)
{
  const std::array<Vec3, 4> rest = { Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1) };
  const double restVolume = signedTetVolume(rest[0], rest[1], rest[2], rest[3]);
  const Contact floor = floorContact(0.0);
  const auto held = heldtet::corners({ &floor, &floor, &floor, nullptr });
  std::array<Vec3, 4> x = rest;
  x[3].z() = 0.2; // V = 0.2 V0: above the least volume, a soft tet the solve may keep so
  for (const Vec3& d : uncrushHeldTet(x, { 1, 1, 1, 1 }, kLeastVolumeFraction * restVolume, held))
  {
    EXPECT_EQ(d, Vec3::Zero());
  }
  x[3].z() = 0.0; // flat, but the only corner that could rise is pinned
  for (const Vec3& d : uncrushHeldTet(x, { 1, 1, 1, 0 }, kLeastVolumeFraction * restVolume, held))
  {
    EXPECT_EQ(d, Vec3::Zero());
  }
}
} // namespace
} // namespace softbody
