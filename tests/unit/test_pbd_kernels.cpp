// Each PBD/XPBD projection kernel on its own: exact restoration, mass weighting, pinned
// particles, gradients against finite differences, XPBD's compliance balance.
#include "softbody/pbd/pbd_kernels.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <functional>

namespace softbody
{
namespace
{
const ProjectionParameters kRigid{}; // PBD stiffness 1 (or XPBD compliance 0), no relaxation

TEST(PbdKernels, StretchedDistanceRestoredInOneProjectionWithEqualMasses)
{
  const Vec3 x0(0, 0, 0), x1(2, 0, 0);
  const Projection<2> p = projectDistance(x0, x1, 1.0, 1.0, 1.0, DistanceKind::Equality, 0.0, kRigid);
  EXPECT_NEAR(((x0 + p.dx[0]) - (x1 + p.dx[1])).norm(), 1.0, 1e-15);
  EXPECT_NEAR(p.dx[0].x(), 0.5, 1e-15); // each end moves half the error
  EXPECT_NEAR(p.dx[1].x(), -0.5, 1e-15);
  EXPECT_DOUBLE_EQ(p.residual, 1.0);
}

TEST(PbdKernels, DistanceCorrectionIsMassWeightedAndKeepsTheCenterOfMass)
{
  const Vec3 x0(0.1, -0.3, 0.2), x1(1.7, 0.4, -0.5);
  const double w0 = 1.0, w1 = 3.0; // masses 1 and 1/3
  const Projection<2> p = projectDistance(x0, x1, w0, w1, 0.8, DistanceKind::Equality, 0.0, kRigid);
  EXPECT_NEAR(p.dx[1].norm() / p.dx[0].norm(), 3.0, 1e-12);
  EXPECT_LT((p.dx[0] / w0 + p.dx[1] / w1).norm(), 1e-15); // sum of m dx = 0
  EXPECT_NEAR(((x0 + p.dx[0]) - (x1 + p.dx[1])).norm(), 0.8, 1e-14);
}

TEST(PbdKernels, PinnedParticleNeverMoves)
{
  const Projection<2> d = projectDistance(Vec3(0, 0, 0), Vec3(3, 1, 0), 0.0, 2.0, 1.0,
    DistanceKind::Equality, 0.0, kRigid);
  EXPECT_EQ(d.dx[0], Vec3::Zero());
  EXPECT_NEAR(((Vec3(3, 1, 0) + d.dx[1])).norm(), 1.0, 1e-14); // the free end does all the work
  const Projection<4> v = projectTetVolume({ Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 3) },
    { 0.0, 1.0, 0.0, 1.0 }, 1.0 / 6.0, 0.0, kRigid);
  EXPECT_EQ(v.dx[0], Vec3::Zero());
  EXPECT_EQ(v.dx[2], Vec3::Zero());
  const Projection<1> plane = projectPlane(Vec3(0, 0, -1), 0.0, Vec3::Zero(), Vec3::UnitZ(), 0.0);
  EXPECT_EQ(plane.dx[0], Vec3::Zero());
  const Projection<2> bothPinned = projectDistance(Vec3(0, 0, 0), Vec3(3, 0, 0), 0.0, 0.0, 1.0,
    DistanceKind::Equality, 0.0, kRigid);
  EXPECT_EQ(bothPinned.dx[1], Vec3::Zero());
  EXPECT_TRUE(std::isfinite(bothPinned.dLambda));
}

TEST(PbdKernels, AtLeastDistanceOnlyPushesApart)
{
  const Projection<2> stretched = projectDistance(Vec3(0, 0, 0), Vec3(2, 0, 0), 1, 1, 1.0,
    DistanceKind::AtLeast, 0.0, kRigid);
  EXPECT_EQ(stretched.dx[0], Vec3::Zero());
  EXPECT_EQ(stretched.residual, 0.0);
  const Projection<2> compressed = projectDistance(Vec3(0, 0, 0), Vec3(0.5, 0, 0), 1, 1, 1.0,
    DistanceKind::AtLeast, 0.0, kRigid);
  EXPECT_NEAR(compressed.dx[0].x(), -0.25, 1e-15);
  EXPECT_NEAR(compressed.dx[1].x(), 0.25, 1e-15);
}

TEST(PbdKernels, VolumeConstraintRestoresTheRestVolume)
{
  std::array<Vec3, 4> x = { Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1) };
  const double rest = signedTetVolume(x[0], x[1], x[2], x[3]);
  for (Vec3& p : x)
  {
    p = Vec3(1.1 * p.x(), p.y(), 0.7 * p.z()) + Vec3(0.01, -0.02, 0.03); // squashed by 23%
  }
  const std::array<double, 4> w = { 1.0, 0.5, 2.0, 1.0 };
  const double before = std::abs(signedTetVolume(x[0], x[1], x[2], x[3]) - rest);
  std::vector<double> errors;
  for (int it = 0; it < 6; ++it)
  {
    const Projection<4> p = projectTetVolume(x, w, rest, 0.0, kRigid);
    Vec3 momentum = Vec3::Zero();
    for (int k = 0; k < 4; ++k)
    {
      x[k] += p.dx[k];
      momentum += p.dx[k] / w[k];
    }
    EXPECT_LT(momentum.norm(), 1e-15); // gradients sum to zero: linear momentum kept
    errors.push_back(std::abs(signedTetVolume(x[0], x[1], x[2], x[3]) - rest));
  }
  EXPECT_LT(errors[0], 0.1 * before);     // one projection removes most of the error
  EXPECT_LT(errors.back(), 1e-12 * rest); // and it converges (quadratically: a Newton step)
}

TEST(PbdKernels, SoftTetCrushedThroughZeroIsPushedBackAboveTheLeastVolume)
{
  // A soft XPBD tet (alphaTilde a million times its stiffness term) inverted by a load: its
  // compliant equality step alone would move it by about a millionth of the way back; the
  // non-inversion inequality takes it back to kLeastVolumeFraction of its rest volume, leaves
  // its multiplier alone, and keeps linear momentum.
  const std::array<Vec3, 4> rest = { Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1) };
  const double restVolume = signedTetVolume(rest[0], rest[1], rest[2], rest[3]);
  std::array<Vec3, 4> x = rest;
  x[3] = Vec3(0.2, 0.3, -0.2); // the apex pushed through the base: V = -0.2 V0
  const std::array<double, 4> w = { 1.0, 0.5, 2.0, 1.0 };
  ProjectionParameters soft;
  soft.alphaTilde = 1e6;
  const double lambda = 0.0; // the first projection of a substep
  std::vector<double> volumes;
  for (int it = 0; it < 4; ++it)
  {
    const Projection<4> p = projectTetVolume(x, w, restVolume, lambda, soft);
    if (it == 0)
    {
      EXPECT_EQ(p.dLambda, 0.0); // the inequality's step: the multiplier stays
    }
    Vec3 momentum = Vec3::Zero();
    for (int k = 0; k < 4; ++k)
    {
      x[k] += p.dx[k];
      momentum += p.dx[k] / w[k];
    }
    EXPECT_LT(momentum.norm(), 1e-15);
    volumes.push_back(signedTetVolume(x[0], x[1], x[2], x[3]));
  }
  // The volume is cubic in the positions: one linearized step un-inverts the tet, the next
  // reach the least volume (a hair above: once there only the soft equality acts).
  const double least = kLeastVolumeFraction * restVolume;
  EXPECT_GT(volumes[0], 0.0);
  EXPECT_GE(volumes.back(), least);
  EXPECT_LT(volumes.back(), 1.01 * least);

  // Above the least volume the soft equality step is the equality's alone: tiny, and it updates
  // lambda.
  x = rest;
  x[3] = Vec3(0.0, 0.0, 0.5); // V = 0.5 V0
  const Projection<4> mild = projectTetVolume(x, w, restVolume, lambda, soft);
  EXPECT_NE(mild.dLambda, 0.0);
  EXPECT_LT(mild.dx[3].norm(), 1e-5);
}

TEST(PbdKernels, StiffTetCrushedTakesTheLargerEqualityStep)
{
  // Rigid (PBD stiffness 1): the equality asks for the whole rest volume, more than the
  // inequality, so an inverted tet is projected as by the equality alone, towards V0, in a
  // Newton step.
  const std::array<Vec3, 4> rest = { Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1) };
  const double restVolume = signedTetVolume(rest[0], rest[1], rest[2], rest[3]);
  std::array<Vec3, 4> x = rest;
  x[3] = Vec3(0.2, 0.3, -0.2);
  const std::array<double, 4> w = { 1.0, 1.0, 1.0, 1.0 };
  for (int it = 0; it < 8; ++it)
  {
    const Projection<4> p = projectTetVolume(x, w, restVolume, 0.0, kRigid);
    EXPECT_NE(p.dLambda, 0.0);
    for (int k = 0; k < 4; ++k)
    {
      x[k] += p.dx[k];
    }
  }
  EXPECT_NEAR(signedTetVolume(x[0], x[1], x[2], x[3]), restVolume, 1e-12 * restVolume);
}

// A projection moves particle k by w_k g_k dLambda; with unit inverse masses, dx_k / dLambda is
// the gradient. Compare with central differences of the constraint function.
void expectGradientMatches(const std::function<double(const std::vector<Vec3>&)>& C,
  std::vector<Vec3> x, const std::vector<Vec3>& dx, double dLambda)
{
  const double h = 1e-6;
  for (std::size_t k = 0; k < x.size(); ++k)
  {
    for (int a = 0; a < 3; ++a)
    {
      std::vector<Vec3> plus = x, minus = x;
      plus[k][a] += h;
      minus[k][a] -= h;
      const double numeric = (C(plus) - C(minus)) / (2 * h);
      EXPECT_NEAR(dx[k][a] / dLambda, numeric, 1e-7 * (1.0 + std::abs(numeric))) << "particle " << k << " axis " << a;
    }
  }
}

TEST(PbdKernels, GradientsMatchFiniteDifferences)
{
  const std::vector<Vec3> x = test::jitter({ Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1) }, 0.2);

  const Projection<2> d = projectDistance(x[0], x[1], 1, 1, 0.3, DistanceKind::Equality, 0.0, kRigid);
  expectGradientMatches([](const std::vector<Vec3>& p) { return (p[0] - p[1]).norm() - 0.3; },
    { x[0], x[1] }, { d.dx[0], d.dx[1] }, d.dLambda);

  const Projection<4> v = projectTetVolume({ x[0], x[1], x[2], x[3] }, { 1, 1, 1, 1 }, 0.05, 0.0, kRigid);
  expectGradientMatches(
    [](const std::vector<Vec3>& p) { return signedTetVolume(p[0], p[1], p[2], p[3]) - 0.05; }, x,
    { v.dx[0], v.dx[1], v.dx[2], v.dx[3] }, v.dLambda);

  const Vec3 target(0.3, -0.2, 0.9);
  const Projection<1> a = projectAttachment(x[2], 1.0, target, 0.0, kRigid);
  expectGradientMatches([&](const std::vector<Vec3>& p) { return (p[0] - target).norm(); }, { x[2] },
    { a.dx[0] }, a.dLambda);

  const Vec3 n = Vec3(0.2, 0.3, 1.0).normalized();
  const Projection<1> f = projectPlane(Vec3(0.1, 0.2, -0.4), 1.0, Vec3::Zero(), n, 0.0);
  expectGradientMatches([&](const std::vector<Vec3>& p) { return n.dot(p[0]); }, { Vec3(0.1, 0.2, -0.4) },
    { f.dx[0] }, f.dLambda);
}

TEST(PbdKernels, SmallViolationIsRemovedToSecondOrder)
{
  // A projection is a Newton step on C: a wrong gradient would leave an O(eps) error.
  std::array<Vec3, 4> x = { Vec3(0, 0, 0), Vec3(1, 0.1, 0), Vec3(0.2, 1, 0), Vec3(0, 0.1, 1) };
  const double V = signedTetVolume(x[0], x[1], x[2], x[3]);
  const double eps = 1e-4 * V;
  const Projection<4> p = projectTetVolume(x, { 1, 2, 1, 0.5 }, V - eps, 0.0, kRigid);
  for (int k = 0; k < 4; ++k)
  {
    x[k] += p.dx[k];
  }
  EXPECT_LT(std::abs(signedTetVolume(x[0], x[1], x[2], x[3]) - (V - eps)), 1e-3 * eps);
}

TEST(PbdKernels, XpbdConvergesToTheComplianceBalance)
{
  // One link, one free end of mass 2: repeated projections converge to C = -alphaTilde lambda,
  // i.e. the end rests where the constraint force lambda / h^2 balances the spring law.
  const double w = 0.5, alpha = 0.01, h = 0.01;
  ProjectionParameters p;
  p.alphaTilde = alpha / (h * h);
  Vec3 x(2.0, 0, 0);
  double lambda = 0.0;
  for (int it = 0; it < 2000; ++it)
  {
    const Projection<2> d = projectDistance(Vec3::Zero(), x, 0.0, w, 1.0, DistanceKind::Equality, lambda, p);
    x += d.dx[1];
    lambda += d.dLambda;
  }
  const double C = x.norm() - 1.0;
  EXPECT_NEAR(C + p.alphaTilde * lambda, 0.0, 1e-12);
  // Displacement from the start is w * lambda (dx = w g dLambda, summed): 1 - C = -w lambda.
  EXPECT_NEAR(2.0 - x.norm(), -w * lambda, 1e-12);
  EXPECT_GT(C, 0.0); // compliance leaves the link stretched
  EXPECT_LT(C, 1.0);
}

TEST(PbdKernels, StiffnessCorrectionMakesTheEffectiveStiffnessIterationIndependent)
{
  for (double k : { 0.01, 0.3, 0.9 })
  {
    for (int n : { 1, 4, 20, 160 })
    {
      const double kPrime = pbdStiffnessPerIteration(k, n);
      // After n projections a linear constraint keeps (1 - k')^n of its error: that must be 1 - k.
      EXPECT_NEAR(std::pow(1.0 - kPrime, n), 1.0 - k, 1e-12) << k << " " << n;
    }
  }
  EXPECT_EQ(pbdStiffnessPerIteration(1.0, 7), 1.0);
}

TEST(PbdKernels, PlaneMovesPenetratingParticlesOutAlongTheNormal)
{
  const Vec3 n = Vec3(0, 1, 1).normalized();
  const Projection<1> in = projectPlane(Vec3(1, -0.2, -0.1), 2.0, Vec3::Zero(), n, 0.05);
  EXPECT_NEAR(n.dot(Vec3(1, -0.2, -0.1) + in.dx[0]), 0.05, 1e-15);
  EXPECT_NEAR(in.dx[0].cross(n).norm(), 0.0, 1e-15);
  const Projection<1> out = projectPlane(Vec3(0, 1, 1), 2.0, Vec3::Zero(), n, 0.05);
  EXPECT_EQ(out.dx[0], Vec3::Zero());
}

} // namespace
} // namespace softbody
