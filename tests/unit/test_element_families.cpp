// The spring network's element families (material/spring_network.h) through the material seam
// (material/element_model.h): gradients against energies and Hessians against gradients by
// central finite differences, rotation invariance, zero gradient at rest, the stiffness bound.
#include "softbody/material/spring_network.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <cmath>
#include <type_traits>

using namespace softbody;

namespace
{

/// One tet with every term on: springs and volume, each with damping (raw constants).
struct OneTet
{
  std::vector<Vec3> rest{ Vec3(0.0, 0.0, 0.0), Vec3(0.1, 0.0, 0.0), Vec3(0.02, 0.09, 0.0),
    Vec3(0.03, 0.02, 0.11) };
  Topology topology;
  ElementConstants constants;
  OneTet()
  {
    topology = buildTopology(4, { { 0, 1, 2, 3 } });
    MaterialSettings raw;
    raw.mode = MaterialMode::Raw;
    raw.raw = { 2.0, 0.05, 3.0, 0.07, 1.0 };
    std::vector<std::string> warnings;
    constants = computeElementConstants(topology, rest, raw, warnings);
  }
};

constexpr double kStep = 0.01; // h [s]

/// Sum over the family's elements of their energies at x [J].
template <ElementFamily F>
double familyEnergy(const F& family, const std::vector<Vec3>& x, const std::vector<Vec3>& x0)
{
  const StepStart start{ x0, kStep };
  double energy = 0.0;
  for (std::size_t e = 0; e < family.size(); ++e)
  {
    typename F::AtX at{};
    energy += family.evaluate(e, x, start, family.stepData(e, x0), at);
  }
  return energy;
}

/// The family's gradient at each point [N], gathered over the corners.
template <ElementFamily F>
std::vector<Vec3> familyGradient(const F& family, const std::vector<Vec3>& x,
  const std::vector<Vec3>& x0)
{
  const StepStart start{ x0, kStep };
  std::vector<typename F::StepData> step(family.size());
  std::vector<typename F::AtX> at(family.size());
  for (std::size_t e = 0; e < family.size(); ++e)
  {
    step[e] = family.stepData(e, x0);
    family.evaluate(e, x, start, step[e], at[e]);
  }
  std::vector<Vec3> gradient(x.size(), Vec3::Zero());
  for (std::size_t i = 0; i < x.size(); ++i)
  {
    family.forEachCorner(static_cast<std::int32_t>(i), [&](std::size_t e, int a) {
      gradient[i] += family.cornerGradient(step[e], at[e], a);
    });
  }
  return gradient;
}

/// Element e's gradient at corner a [N].
template <ElementFamily F>
Vec3 cornerGradient(const F& family, std::size_t e, int a, const std::vector<Vec3>& x,
  const std::vector<Vec3>& x0)
{
  const StepStart start{ x0, kStep };
  const typename F::StepData step = family.stepData(e, x0);
  typename F::AtX at{};
  family.evaluate(e, x, start, step, at);
  return family.cornerGradient(step, at, a);
}

/// Element e's Hessian block (a, b) [N/m].
template <ElementFamily F>
Mat3 hessianBlock(const F& family, std::size_t e, int a, int b, const std::vector<Vec3>& x,
  const std::vector<Vec3>& x0)
{
  const StepStart start{ x0, kStep };
  const typename F::StepData step = family.stepData(e, x0);
  typename F::AtX at{};
  family.evaluate(e, x, start, step, at);
  const typename F::HessianData local = family.hessianData(e, x, start, step, at);
  return family.hessianBlock(step, at, local, a, b);
}

template <ElementFamily F>
void expectGradientMatchesEnergy(const F& family, const std::vector<Vec3>& x,
  const std::vector<Vec3>& x0)
{
  const std::vector<Vec3> gradient = familyGradient(family, x, x0);
  const double eps = 1e-7;
  double scale = 0.0;
  for (const Vec3& g : gradient)
  {
    scale = std::max(scale, g.norm());
  }
  ASSERT_GT(scale, 0.0);
  for (std::size_t i = 0; i < x.size(); ++i)
  {
    for (int k = 0; k < 3; ++k)
    {
      std::vector<Vec3> plus = x, minus = x;
      plus[i][k] += eps;
      minus[i][k] -= eps;
      const double numeric =
        (familyEnergy(family, plus, x0) - familyEnergy(family, minus, x0)) / (2.0 * eps);
      EXPECT_NEAR(gradient[i][k], numeric, 1e-6 * scale) << "point " << i << " axis " << k;
    }
  }
}

/// Every block (a, b) of every element against the central difference of the corner gradient.
template <ElementFamily F>
void expectHessianMatchesGradient(const F& family, const std::vector<Vec3>& x,
  const std::vector<Vec3>& x0)
{
  const double eps = 1e-7;
  for (std::size_t e = 0; e < family.size(); ++e)
  {
    const auto corners = family.corners(e);
    for (int a = 0; a < F::kCorners; ++a)
    {
      for (int b = 0; b < F::kCorners; ++b)
      {
        const Mat3 block = hessianBlock(family, e, a, b, x, x0);
        for (int k = 0; k < 3; ++k)
        {
          std::vector<Vec3> plus = x, minus = x;
          plus[static_cast<std::size_t>(corners[static_cast<std::size_t>(b)])][k] += eps;
          minus[static_cast<std::size_t>(corners[static_cast<std::size_t>(b)])][k] -= eps;
          const Vec3 numeric = (cornerGradient(family, e, a, plus, x0) -
                                 cornerGradient(family, e, a, minus, x0)) /
            (2.0 * eps);
          const double scale = std::max(1e-12, block.norm());
          EXPECT_LT((block.col(k) - numeric).norm(), 1e-6 * scale)
            << "element " << e << " block (" << a << ", " << b << ") column " << k;
        }
      }
    }
  }
}

std::vector<Vec3> rotated(const std::vector<Vec3>& points, const Mat3& rotation, const Vec3& shift)
{
  std::vector<Vec3> result;
  for (const Vec3& p : points)
  {
    result.push_back(rotation * p + shift);
  }
  return result;
}

Mat3 someRotation()
{
  return Eigen::AngleAxisd(1.1, Vec3(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
}

} // namespace

TEST(ElementFamilies, SpringGradientMatchesEnergy)
{
  const OneTet body;
  const SpringFamily springs(body.topology, body.constants);
  const std::vector<Vec3> x0 = test::jitter(body.rest, 0.01, 3);
  const std::vector<Vec3> x = test::jitter(body.rest, 0.02, 5); // some springs stretched, some compressed
  expectGradientMatchesEnergy(springs, x, x0);
}

TEST(ElementFamilies, VolumeGradientMatchesEnergy)
{
  const OneTet body;
  const VolumeFamily volumes(body.topology, body.constants);
  ASSERT_EQ(volumes.size(), 1u);
  const std::vector<Vec3> x0 = test::jitter(body.rest, 0.01, 3);
  const std::vector<Vec3> x = test::jitter(body.rest, 0.02, 5);
  expectGradientMatchesEnergy(volumes, x, x0);
}

TEST(ElementFamilies, StretchedSpringHessianMatchesGradient)
{
  // Every spring longer than its rest length: the transverse stiffness k (1 - l0/l) is
  // positive, the projection does nothing, and the blocks are the exact Hessian (damping
  // included: its energy is quadratic along the frozen axes).
  const OneTet body;
  const SpringFamily springs(body.topology, body.constants);
  const std::vector<Vec3> x = rotated(body.rest, 1.3 * someRotation(), Vec3(0.2, -0.1, 0.05));
  const std::vector<Vec3> x0 = test::jitter(body.rest, 0.01, 3);
  for (std::size_t e = 0; e < springs.size(); ++e)
  {
    const Edge& edge = body.topology.edges[e];
    ASSERT_GT((x[edge.a] - x[edge.b]).norm(), body.constants.restLength[e]);
  }
  expectHessianMatchesGradient(springs, x, x0);
}

TEST(ElementFamilies, TetAtRestVolumeHessianMatchesGradient)
{
  // A sheared and rotated tet of volume V0: the dropped curvature K (V - V0) d2V/dx2 vanishes,
  // and with x0 = x the damping block (Kd / h) g g^T is the exact one (g0 = g), so the
  // Gauss-Newton blocks are the exact Hessian.
  const OneTet body;
  const VolumeFamily volumes(body.topology, body.constants);
  std::vector<Vec3> sheared = body.rest;
  for (Vec3& p : sheared)
  {
    p.x() += 0.4 * p.z(); // volume preserving
  }
  const std::vector<Vec3> x = rotated(sheared, someRotation(), Vec3(0.1, 0.2, 0.3));
  const auto& t = body.topology.tets[0];
  ASSERT_NEAR(signedTetVolume(x[t[0]], x[t[1]], x[t[2]], x[t[3]]), body.constants.restVolume[0],
    1e-12 * body.constants.restVolume[0]);
  expectHessianMatchesGradient(volumes, x, x);

  // Along the Gauss-Newton direction itself (d = g) near V0, d^T H d against the second
  // difference of the energy.
  const auto g = tetVolumeGradients(x[t[0]], x[t[1]], x[t[2]], x[t[3]]);
  double dHd = 0.0;
  for (int a = 0; a < 4; ++a)
  {
    for (int b = 0; b < 4; ++b)
    {
      dHd += g[static_cast<std::size_t>(a)].dot(
        hessianBlock(volumes, 0, a, b, x, x) * g[static_cast<std::size_t>(b)]);
    }
  }
  const double eps = 1e-5;
  std::vector<Vec3> plus = x, minus = x;
  for (int a = 0; a < 4; ++a)
  {
    plus[static_cast<std::size_t>(t[a])] += eps * g[static_cast<std::size_t>(a)];
    minus[static_cast<std::size_t>(t[a])] -= eps * g[static_cast<std::size_t>(a)];
  }
  const double numeric = (familyEnergy(volumes, plus, x) - 2.0 * familyEnergy(volumes, x, x) +
                           familyEnergy(volumes, minus, x)) /
    (eps * eps);
  EXPECT_NEAR(dHd, numeric, 1e-5 * dHd);
}

TEST(ElementFamilies, EnergyIsRotationInvariant)
{
  const OneTet body;
  const SpringFamily springs(body.topology, body.constants);
  const VolumeFamily volumes(body.topology, body.constants);
  const std::vector<Vec3> x0 = test::jitter(body.rest, 0.01, 3);
  const std::vector<Vec3> x = test::jitter(body.rest, 0.02, 5);
  const Mat3 r = someRotation();
  const Vec3 shift(0.5, -0.2, 0.1);
  const std::vector<Vec3> rx = rotated(x, r, shift), rx0 = rotated(x0, r, shift);
  const double springEnergy = familyEnergy(springs, x, x0);
  const double volumeEnergy = familyEnergy(volumes, x, x0);
  ASSERT_GT(springEnergy, 0.0);
  ASSERT_GT(volumeEnergy, 0.0);
  EXPECT_NEAR(familyEnergy(springs, rx, rx0), springEnergy, 1e-12 * springEnergy);
  EXPECT_NEAR(familyEnergy(volumes, rx, rx0), volumeEnergy, 1e-12 * volumeEnergy);
  // Elastic energy alone (no motion in the step): rotating only x changes nothing either.
  EXPECT_NEAR(familyEnergy(springs, rx, rx), familyEnergy(springs, x, x), 1e-12 * springEnergy);
  EXPECT_NEAR(familyEnergy(volumes, rx, rx), familyEnergy(volumes, x, x), 1e-12 * volumeEnergy);
}

TEST(ElementFamilies, GradientIsZeroAtRest)
{
  const OneTet body;
  const SpringFamily springs(body.topology, body.constants);
  const VolumeFamily volumes(body.topology, body.constants);
  const std::vector<Vec3> x = rotated(body.rest, someRotation(), Vec3(1.0, 2.0, 3.0));
  // A force scale: one spring stretched by 1%.
  const double scale = 0.01 * body.constants.springStiffness[0] * body.constants.restLength[0];
  for (const Vec3& g : familyGradient(springs, x, x))
  {
    EXPECT_LT(g.norm(), 1e-9 * scale);
  }
  for (const Vec3& g : familyGradient(volumes, x, x))
  {
    EXPECT_LT(g.norm(), 1e-9 * scale);
  }
  EXPECT_NEAR(familyEnergy(springs, x, x), 0.0, 1e-20);
  EXPECT_NEAR(familyEnergy(volumes, x, x), 0.0, 1e-20);
}

TEST(ElementFamilies, StiffnessBoundCoversTheRestHessian)
{
  // At rest (x0 = x, so the damping blocks are included too, scaled by h / (h + beta)) the
  // elastic blocks' row norms stay under the bound.
  const OneTet body;
  const SpringFamily springs(body.topology, body.constants);
  const VolumeFamily volumes(body.topology, body.constants);
  const auto check = [&](const auto& family) {
    using F = std::remove_cvref_t<decltype(family)>;
    for (std::size_t e = 0; e < family.size(); ++e)
    {
      for (int a = 0; a < F::kCorners; ++a)
      {
        double rowNorm = 0.0;
        for (int b = 0; b < F::kCorners; ++b)
        {
          rowNorm += hessianBlock(family, e, a, b, body.rest, body.rest).operatorNorm();
        }
        EXPECT_GT(rowNorm, 0.0);
        // The blocks include damping (kd / h): compare the bound with the elastic share.
        const double elasticShare = 1.0 /
          (1.0 + (F::kCorners == 2 ? body.constants.springDamping[e] / body.constants.springStiffness[e]
                                   : body.constants.volumeDamping[e] / body.constants.volumeStiffness[e]) /
              kStep);
        EXPECT_LE(elasticShare * rowNorm, family.stiffnessBound(e, a, body.rest) * (1.0 + 1e-12))
          << "element " << e << " corner " << a;
      }
    }
  };
  check(springs);
  check(volumes);
}
