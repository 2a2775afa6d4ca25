// The continuum laws and their tet family: the stress is the energy's gradient and the stress
// derivative its Hessian (finite differences, inverted deformations included), the projection
// is positive semi-definite and exact where the derivative already is, the small-strain limit is
// linear elasticity of the typed E and nu (Stable Neo-Hookean through its re-parameterization),
// flat and inverted tets are finite and pushed back, and the family's corner gradients and
// Hessian blocks are the derivatives of its element energy, damping included.
#include "softbody/material/tet_elastic_forces.h"
#include "softbody/material/tet_elasticity.h"

#include "softbody/mesh/mesh_generators.h"
#include "softbody/mesh/topology.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <random>

using namespace softbody;

namespace
{

const LameParameters kLinear = lameFromYoung(1.0e5, 0.3);

Mat3 randomDeformation(unsigned seed, double spread)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-spread, spread);
  Mat3 f = Mat3::Identity();
  for (int k = 0; k < 9; ++k)
  {
    f(k / 3, k % 3) += u(rng);
  }
  return f;
}

/// A deformation that turns the element inside out (det < 0).
Mat3 invertedDeformation(unsigned seed)
{
  Mat3 f = randomDeformation(seed, 0.2);
  f.col(2) *= -0.6;
  return f;
}

template <class Law>
double energyOf(const Mat3& f, const LameParameters& p)
{
  return Law::energy(rotationVariantSvd(f).s, p);
}

template <class Law>
Mat3 stressOf(const Mat3& f, const LameParameters& p)
{
  return firstPiolaStress<Law>(rotationVariantSvd(f), p);
}

template <class Law>
void expectStressIsTheEnergyGradient(const Mat3& f)
{
  const LameParameters p = Law::fromLinear(kLinear);
  const Mat3 stress = stressOf<Law>(f, p);
  const double eps = 1e-6;
  for (int k = 0; k < 9; ++k)
  {
    Mat3 step = Mat3::Zero();
    step(k / 3, k % 3) = eps;
    const double numeric = (energyOf<Law>(f + step, p) - energyOf<Law>(f - step, p)) / (2 * eps);
    EXPECT_NEAR(stress(k / 3, k % 3), numeric, 1e-6 * kLinear.mu) << Law::kName << " entry " << k;
  }
}

template <class Law>
void expectDerivativeMatchesFiniteDifferences(const Mat3& f)
{
  const LameParameters p = Law::fromLinear(kLinear);
  const Mat9 exact = stressDerivative<Law>(rotationVariantSvd(f), p, false);
  const double eps = 1e-6;
  double worst = 0.0;
  for (int k = 0; k < 9; ++k)
  {
    Mat3 step = Mat3::Zero();
    step(k / 3, k % 3) = eps;
    const Vec9 numeric = flatten(stressOf<Law>(f + step, p) - stressOf<Law>(f - step, p)) / (2 * eps);
    worst = std::max(worst, (exact.col(k) - numeric).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-5 * exact.cwiseAbs().maxCoeff()) << Law::kName << "\n" << f;
}

} // namespace

TEST(IsotropicLaws, StressIsTheEnergyGradientForStretchedAndInvertedTets)
{
  for (unsigned seed = 1; seed <= 4; ++seed)
  {
    expectStressIsTheEnergyGradient<CorotatedLaw>(randomDeformation(seed, 0.4));
    expectStressIsTheEnergyGradient<StableNeoHookeanLaw>(randomDeformation(seed, 0.4));
    expectStressIsTheEnergyGradient<CorotatedLaw>(invertedDeformation(seed));
    expectStressIsTheEnergyGradient<StableNeoHookeanLaw>(invertedDeformation(seed));
  }
}

TEST(IsotropicLaws, ClosedFormEigensystemIsTheStressDerivative)
{
  for (unsigned seed = 1; seed <= 4; ++seed)
  {
    expectDerivativeMatchesFiniteDifferences<CorotatedLaw>(randomDeformation(seed, 0.4));
    expectDerivativeMatchesFiniteDifferences<StableNeoHookeanLaw>(randomDeformation(seed, 0.4));
    expectDerivativeMatchesFiniteDifferences<CorotatedLaw>(invertedDeformation(seed));
    expectDerivativeMatchesFiniteDifferences<StableNeoHookeanLaw>(invertedDeformation(seed));
  }
  // Repeated singular values (a uniform stretch): the closed forms need no division there.
  expectDerivativeMatchesFiniteDifferences<CorotatedLaw>(1.2 * Mat3::Identity());
  expectDerivativeMatchesFiniteDifferences<StableNeoHookeanLaw>(0.8 * Mat3::Identity());
}

template <class Law>
void expectProjectionIsExactAndPositive()
{
  const LameParameters p = Law::fromLinear(kLinear);
  for (unsigned seed = 1; seed <= 6; ++seed)
  {
    const Mat3 f = seed % 2 ? invertedDeformation(seed) : randomDeformation(seed, 0.6);
    const RotationVariantSvd svd = rotationVariantSvd(f);
    const Mat9 exact = stressDerivative<Law>(svd, p, false);
    const Mat9 projected = stressDerivative<Law>(svd, p, true);
    const Eigen::SelfAdjointEigenSolver<Mat9> exactEigen(exact), projectedEigen(projected);
    const double scale = exactEigen.eigenvalues().cwiseAbs().maxCoeff();
    EXPECT_GT(projectedEigen.eigenvalues().minCoeff(), -1e-10 * scale) << Law::kName;
    // The projection keeps every positive eigenpair and clamps the others: the same as
    // clamping a numerical eigendecomposition of the exact derivative.
    Mat9 clamped = Mat9::Zero();
    for (int k = 0; k < 9; ++k)
    {
      const double value = std::max(exactEigen.eigenvalues()(k), 0.0);
      clamped += value * exactEigen.eigenvectors().col(k) * exactEigen.eigenvectors().col(k).transpose();
    }
    EXPECT_LT((projected - clamped).cwiseAbs().maxCoeff(), 1e-9 * scale) << Law::kName << " " << seed;
  }
}

TEST(IsotropicLaws, ProjectionClampsExactlyTheNegativeEigenvalues)
{
  expectProjectionIsExactAndPositive<CorotatedLaw>();
  expectProjectionIsExactAndPositive<StableNeoHookeanLaw>();
}

template <class Law>
void expectLinearElasticityAtRest(double poissonRatio)
{
  const LameParameters linear = lameFromYoung(2.0e6, poissonRatio);
  const LameParameters p = Law::fromLinear(linear);
  const RotationVariantSvd rest = rotationVariantSvd(Mat3::Identity());
  EXPECT_LT(firstPiolaStress<Law>(rest, p).norm(), 1e-9 * linear.mu) << "stress at rest";
  EXPECT_NEAR(Law::energy(rest.s, p), 0.0, 1e-9 * linear.mu) << "energy at rest";
  const Mat9 tangent = stressDerivative<Law>(rest, p, false);
  const Mat3 h = randomDeformation(3, 1.0) - Mat3::Identity();
  const Mat3 expected = linear.mu * (h + h.transpose()) + linear.lambda * h.trace() * Mat3::Identity();
  const Vec9 got = tangent * flatten(h);
  // Relative to the largest modulus: at nu near 0.5 lambda dwarfs the answer's other terms.
  EXPECT_LT((got - flatten(expected)).cwiseAbs().maxCoeff(), 1e-12 * (linear.mu + std::abs(linear.lambda)) * h.norm())
    << Law::kName << " nu " << poissonRatio;
}

TEST(IsotropicLaws, SmallStrainLimitIsLinearElasticityOfTheTypedModuli)
{
  for (double nu : { -0.5, 0.0, 0.3, 0.45, 0.499 })
  {
    expectLinearElasticityAtRest<CorotatedLaw>(nu);
    expectLinearElasticityAtRest<StableNeoHookeanLaw>(nu);
  }
}

template <class Law>
void expectPushedBackFrom(const Mat3& f)
{
  const LameParameters p = Law::fromLinear(kLinear);
  const Mat3 stress = stressOf<Law>(f, p);
  EXPECT_TRUE(std::isfinite(energyOf<Law>(f, p)) && stress.allFinite()) << Law::kName;
  // Moving against the stress (-P) changes J by -cof(F) : P: it must grow.
  Mat3 cofactor;
  cofactor.col(0) = f.col(1).cross(f.col(2));
  cofactor.col(1) = f.col(2).cross(f.col(0));
  cofactor.col(2) = f.col(0).cross(f.col(1));
  EXPECT_LT((cofactor.cwiseProduct(stress)).sum(), 0.0) << Law::kName << "\n" << f;
}

TEST(IsotropicLaws, FlatAndInvertedTetsHaveFiniteEnergyAndArePushedBack)
{
  const Mat3 flat = Vec3(1.0, 1.0, 0.0).asDiagonal();
  const Mat3 inverted = Vec3(1.0, 1.0, -0.5).asDiagonal();
  for (const Mat3& f : { flat, inverted, invertedDeformation(5) })
  {
    expectPushedBackFrom<CorotatedLaw>(f);
    expectPushedBackFrom<StableNeoHookeanLaw>(f);
  }
}

namespace
{

/// One tet of the family with its step data, for the derivative checks below.
template <class Law>
struct OneTet
{
  Topology topology = buildTopology(4, { Tet{ 0, 1, 2, 3 } });
  std::vector<Vec3> rest{ Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0.02, 0.09, 0), Vec3(0.01, 0.03, 0.11) };
  TetElasticConstants constants;
  OneTet()
  {
    MaterialSettings material;
    material.model = std::is_same_v<Law, CorotatedLaw> ? MaterialModel::Corotated
                                                       : MaterialModel::StableNeoHookean;
    material.physical.dampingTime = 0.01;
    std::vector<std::string> warnings;
    constants = computeTetElasticConstants(topology, rest, material, warnings);
  }
};

template <class Law>
void expectFamilyDerivatives(double displacement)
{
  OneTet<Law> tet;
  const TetElasticFamily<Law> family(tet.topology, tet.constants);
  const std::vector<Vec3> x0 = test::jitter(tet.rest, 0.1 * displacement, 3);
  const std::vector<Vec3> x = test::jitter(tet.rest, displacement, 9);
  const StepStart start{ x0, 1.0 / 60 };
  const auto step = family.stepData(0, x0);
  typename TetElasticFamily<Law>::AtX at;
  family.evaluate(0, x, start, step, at);
  // Translation invariance: the corner forces balance.
  Vec3 total = Vec3::Zero();
  for (int c = 0; c < 4; ++c)
  {
    total += family.cornerGradient(step, at, c);
  }
  EXPECT_LT(total.norm(), 1e-9 * family.cornerGradient(step, at, 0).norm());
  const double eps = 1e-7;
  const auto hessian = family.hessianData(0, x, start, step, at);
  double worstGradient = 0.0, worstHessian = 0.0, gradientScale = 0.0, hessianScale = 0.0;
  for (int b = 0; b < 4; ++b)
  {
    for (int beta = 0; beta < 3; ++beta)
    {
      std::vector<Vec3> plus = x, minus = x;
      plus[b](beta) += eps;
      minus[b](beta) -= eps;
      typename TetElasticFamily<Law>::AtX atPlus, atMinus;
      const double ePlus = family.evaluate(0, plus, start, step, atPlus);
      const double eMinus = family.evaluate(0, minus, start, step, atMinus);
      const double numeric = (ePlus - eMinus) / (2 * eps);
      worstGradient = std::max(worstGradient, std::abs(family.cornerGradient(step, at, b)(beta) - numeric));
      gradientScale = std::max(gradientScale, std::abs(numeric));
      for (int a = 0; a < 4; ++a)
      {
        const Vec3 column = (family.cornerGradient(step, atPlus, a) - family.cornerGradient(step, atMinus, a)) / (2 * eps);
        const Vec3 exact = family.hessianBlock(step, at, hessian, a, b).col(beta);
        worstHessian = std::max(worstHessian, (exact - column).cwiseAbs().maxCoeff());
        hessianScale = std::max(hessianScale, column.cwiseAbs().maxCoeff());
      }
    }
  }
  EXPECT_LT(worstGradient, 1e-6 * gradientScale) << Law::kName;
  EXPECT_LT(worstHessian, 1e-5 * hessianScale) << Law::kName;
}

} // namespace

TEST(TetElasticFamily, GradientsAndHessianBlocksAreTheElementEnergysDerivatives)
{
  // Near rest the elastic derivative is positive definite, so its projection is exact and the
  // blocks must equal the numerical Hessian (damping's exact Hessian included).
  expectFamilyDerivatives<CorotatedLaw>(1e-3);
  expectFamilyDerivatives<StableNeoHookeanLaw>(1e-3);
}

TEST(TetElasticFamily, StiffnessBoundCoversTheRestHessiansRows)
{
  OneTet<StableNeoHookeanLaw> tet;
  const TetElasticFamily<StableNeoHookeanLaw> family(tet.topology, tet.constants);
  const StepStart start{ tet.rest, 1.0 };
  TetElasticConstants undamped = tet.constants;
  undamped.damped = false;
  const TetElasticFamily<StableNeoHookeanLaw> elastic(tet.topology, undamped);
  const auto step = elastic.stepData(0, tet.rest);
  typename TetElasticFamily<StableNeoHookeanLaw>::AtX at;
  elastic.evaluate(0, tet.rest, start, step, at);
  const auto hessian = elastic.hessianData(0, tet.rest, start, step, at);
  for (int a = 0; a < 4; ++a)
  {
    double row = 0.0;
    for (int b = 0; b < 4; ++b)
    {
      row += elastic.hessianBlock(step, at, hessian, a, b).operatorNorm();
    }
    EXPECT_LE(row, family.stiffnessBound(0, a, tet.rest) * (1 + 1e-12));
    EXPECT_GT(row, 0.2 * family.stiffnessBound(0, a, tet.rest)) << "a bound this loose costs steps";
  }
}

TEST(IsotropicLaws, StableNeoHookeansClosedFormInFIsItsSingularValueForm)
{
  const LameParameters p = StableNeoHookeanLaw::fromLinear(kLinear);
  for (unsigned seed = 1; seed <= 4; ++seed)
  {
    for (const Mat3& f : { randomDeformation(seed, 0.5), invertedDeformation(seed) })
    {
      Mat3 stress;
      const double energy = StableNeoHookeanLaw::energyAndStressOf(f, p, stress);
      EXPECT_NEAR(energy, energyOf<StableNeoHookeanLaw>(f, p), 1e-12 * kLinear.mu);
      EXPECT_LT((stress - stressOf<StableNeoHookeanLaw>(f, p)).norm(), 1e-10 * kLinear.mu);
    }
  }
}

TEST(TetElasticFamily, ViscosityLeavesARigidRotationUndamped)
{
  // A turned body spinning rigidly feels no viscous force; the same speeds stretching it do.
  const TetMesh box = makeTetBox(2, 2, 2, 0.05);
  const Topology topology = buildTopology(box.points.size(), box.tets);
  MaterialSettings material;
  material.model = MaterialModel::Corotated;
  material.physical.dampingTime = 0.05;
  std::vector<std::string> warnings;
  const TetElasticConstants constants = computeTetElasticConstants(topology, box.points, material, warnings);
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Vec3 spin(0.3, -1.1, 0.4);
  std::vector<Vec3> x, rigid, stretching;
  for (const Vec3& p : box.points)
  {
    x.push_back(turn * p);
    rigid.push_back(spin.cross(turn * p));
    stretching.push_back(Vec3(spin.norm() * (turn * p).x(), 0, 0));
  }
  TetElasticScratch scratch;
  std::vector<Vec3> spun, stretched;
  computeTetElasticForces(topology, constants, x, rigid, scratch, spun);
  computeTetElasticForces(topology, constants, x, stretching, scratch, stretched);
  double spunMax = 0.0, stretchedMax = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i)
  {
    spunMax = std::max(spunMax, spun[i].norm());
    stretchedMax = std::max(stretchedMax, stretched[i].norm());
  }
  EXPECT_GT(stretchedMax, 0.0);
  EXPECT_LT(spunMax, 1e-9 * stretchedMax);
}

// The closed-form SVD (the fast path) against JacobiSVD on stretched, rotated, inverted,
// nearly flat and nearly isotropic deformations: where it is taken, the same singular values,
// the same nearest rotation U V^T and the same Corotated stress to 1e-10 of their size; where
// it is set aside, rotationVariantSvd gives JacobiSVD's own answer. Most random deformations
// take it (else it would be no faster).
TEST(IsotropicLaws, ClosedFormSvdIsJacobiSvdsWhereItIsTaken)
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> angle(-3.0, 3.0);
  std::vector<Mat3> cases;
  for (unsigned k = 0; k < 400; ++k)
  {
    const Mat3 rotation =
      (Eigen::AngleAxisd(angle(rng), Vec3::UnitZ()) * Eigen::AngleAxisd(angle(rng), Vec3::UnitX())).toRotationMatrix();
    const Mat3 base = k % 4 == 0 ? invertedDeformation(k) : randomDeformation(k, k % 4 == 1 ? 1e-7 : 0.5);
    Mat3 f = rotation * base;
    if (k % 8 == 3)
    {
      f.col(2) *= 1e-9; // nearly flat
    }
    cases.push_back(f);
  }
  cases.push_back(Mat3::Identity());
  cases.push_back(Mat3::Zero());
  cases.push_back(Vec3(2.0, 2.0, -1e-3).asDiagonal());
  int taken = 0;
  for (const Mat3& f : cases)
  {
    const RotationVariantSvd jacobi = rotationVariantSvdJacobi(f);
    RotationVariantSvd closed;
    const double size = std::max(f.norm(), 1e-300);
    if (!rotationVariantSvdClosedForm(f, closed))
    {
      const RotationVariantSvd chosen = rotationVariantSvd(f);
      EXPECT_EQ(chosen.s, jacobi.s);
      EXPECT_EQ(chosen.u, jacobi.u);
      continue;
    }
    ++taken;
    EXPECT_LT((closed.s - jacobi.s).cwiseAbs().maxCoeff(), 1e-10 * size) << f;
    EXPECT_NEAR(closed.u.determinant(), 1.0, 1e-12);
    EXPECT_NEAR(closed.v.determinant(), 1.0, 1e-12);
    if (jacobi.s(1) - std::abs(jacobi.s(2)) > 1e-6 * size) // the rotation is unique
    {
      EXPECT_LT((closed.u * closed.v.transpose() - jacobi.u * jacobi.v.transpose()).norm(), 1e-8) << f;
    }
    const LameParameters p = kLinear;
    const Mat3 stress = firstPiolaStress<CorotatedLaw>(closed, p);
    const Mat3 reference = firstPiolaStress<CorotatedLaw>(jacobi, p);
    EXPECT_LT((stress - reference).norm(), 1e-8 * (reference.norm() + p.mu)) << f;
  }
  std::printf("closed form taken for %d of %zu deformations\n", taken, cases.size());
  EXPECT_GT(taken, static_cast<int>(cases.size()) * 3 / 4);
}
