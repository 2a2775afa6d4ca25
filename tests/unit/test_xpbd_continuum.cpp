// The continuum models under XPBD (material/constraint_forms.h, pbd_tet_elastic_kernel.h): the
// constraints' energy is the law's (up to a constant) and their force its stress, the coupled
// projection solves its linearized system, a converged XPBD step is Implicit Euler's step of
// the same law, the hanging bar and the patch test land where the mass-spring static solve puts
// them, a crushed body recovers, the result does not depend on the thread count, and what has
// no meaning is refused quoting the value.
#include "softbody/common/errors.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/material/constraint_forms.h"
#include "softbody/mesh/mesh_generators.h"
#include "softbody/pbd/pbd_plan.h"
#include "softbody/pbd/pbd_simulation.h"
#include "softbody/pbd/pbd_tet_elastic_kernel.h"
#include "static_equilibrium.h"
#include "test_support.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

using namespace softbody;

namespace
{

constexpr MaterialModel kModels[] = { MaterialModel::Corotated, MaterialModel::StableNeoHookean };

Mat3 randomDeformation(std::mt19937& rng, double spread)
{
  std::uniform_real_distribution<double> u(-spread, spread);
  Mat3 f = Mat3::Identity();
  for (int i = 0; i < 3; ++i)
  {
    for (int j = 0; j < 3; ++j)
    {
      f(i, j) += u(rng);
    }
  }
  return f;
}

/// The law's energy density and stress at F, through its singular values.
template <class Law>
double lawEnergy(const Mat3& f, const LameParameters& p, Mat3& stress)
{
  const RotationVariantSvd svd = rotationVariantSvd(f);
  stress = svd.u * Law::gradient(svd.s, p).asDiagonal() * svd.v.transpose();
  return Law::energy(svd.s, p);
}

/// The constraints' energy kD/2 C_D^2 + kH/2 (J - Jrest)^2 and its derivative in F.
template <class Law>
double constraintEnergy(const Mat3& f, const LameParameters& p, Mat3& stress)
{
  using Form = ConstraintForm<Law>;
  const DeviatoricConstraint d = Form::deviatoric(f);
  const double kD = Form::deviatoricStiffness(p), kH = Form::hydrostaticStiffness(p);
  const double cH = f.determinant() - Form::restJ(p);
  stress = kD * d.value * d.gradient + kH * cH * cofactor(f);
  return 0.5 * kD * d.value * d.value + 0.5 * kH * cH * cH;
}

template <class Law>
void expectConstraintsAreTheLaw()
{
  const LameParameters p = Law::fromLinear(lameFromYoung(1.0e5, 0.3));
  Mat3 unused;
  const double offset = constraintEnergy<Law>(Mat3::Identity(), p, unused) - lawEnergy<Law>(Mat3::Identity(), p, unused);
  std::mt19937 rng(3);
  double worstEnergy = 0.0, worstStress = 0.0, worstGradient = 0.0;
  for (int k = 0; k < 200; ++k)
  {
    Mat3 f = randomDeformation(rng, 0.6);
    if (k % 4 == 0)
    {
      f.col(2) *= -1.0; // inverted
    }
    Mat3 lawStress, constraintStress;
    const double law = lawEnergy<Law>(f, p, lawStress);
    const double constraints = constraintEnergy<Law>(f, p, constraintStress);
    worstEnergy = std::max(worstEnergy, std::abs(constraints - offset - law) / (p.mu * (1.0 + f.squaredNorm())));
    worstStress = std::max(worstStress, (constraintStress - lawStress).norm() / (p.mu * (1.0 + f.norm())));
    // dC_D/dF against central differences of C_D.
    const DeviatoricConstraint d = ConstraintForm<Law>::deviatoric(f);
    const double step = 1e-6;
    for (int i = 0; i < 3; ++i)
    {
      for (int j = 0; j < 3; ++j)
      {
        Mat3 plus = f, minus = f;
        plus(i, j) += step;
        minus(i, j) -= step;
        const double numeric = (ConstraintForm<Law>::deviatoric(plus).value - ConstraintForm<Law>::deviatoric(minus).value) / (2 * step);
        worstGradient = std::max(worstGradient, std::abs(numeric - d.gradient(i, j)));
      }
    }
  }
  std::printf("%s: energy %.2e, stress %.2e (relative to mu), dC_D/dF %.2e from differences\n",
    Law::kName, worstEnergy, worstStress, worstGradient);
  EXPECT_LT(worstEnergy, 1e-12) << Law::kName;
  EXPECT_LT(worstStress, 1e-10) << Law::kName;
  EXPECT_LT(worstGradient, 1e-7) << Law::kName;
}

/// The mesh as a body of `model` with Young's modulus E [Pa], Poisson's ratio nu and density
/// rho [kg/m^3], its mass lumped as the finite elements' is.
Body xpbdBody(const TetMesh& mesh, MaterialModel model, double E, double nu, double rho)
{
  Body body;
  body.mesh.points = mesh.points;
  body.mesh.tets = mesh.tets;
  body.material.model = model;
  body.material.physical = { E, nu, rho, 0.0 };
  body.material.massDistribution = MassDistribution::LumpedVolume;
  return body;
}

PbdSettings xpbdSettings()
{
  PbdSettings settings;
  settings.elasticFromMaterial = true;
  settings.collisions.mode = CollisionMode::Off;
  settings.reportConvergence = false;
  return settings;
}

std::string refusal(const Body& body, const PbdSettings& settings)
{
  return test::refusalOf<PbdSimulation>(body, settings);
}

} // namespace

TEST(XpbdContinuum, ConstraintEnergyIsTheLawsEnergyAndItsForceTheLawsStress)
{
  expectConstraintsAreTheLaw<CorotatedLaw>();
  expectConstraintsAreTheLaw<StableNeoHookeanLaw>();
}

TEST(XpbdContinuum, CoupledProjectionSolvesItsLinearizedConstraints)
{
  // After one projection from lambda = 0, each constraint's linearization at the start holds:
  // C_i + sum_k g_ik . dx_k + aTilde_i dLambda_i = 0 (the 2 x 2 system, solved exactly).
  const TetMesh tet = makeTetBox(1, 1, 1, 1.0);
  std::mt19937 rng(9);
  for (MaterialModel model : kModels)
  {
    const PbdSimulation sim(xpbdBody(tet, model, 1.0e5, 0.3, 1000.0), xpbdSettings());
    const TetElasticBatch& batch = sim.tetElasticity();
    ASSERT_GT(batch.size(), 0u);
    const Mat3 deform = randomDeformation(rng, 0.3);
    std::vector<Vec3> x(tet.points.size());
    for (std::size_t i = 0; i < x.size(); ++i)
    {
      x[i] = deform * tet.points[i];
    }
    const std::array<double, 4> w{ 0.5, 1.0, 2.0, 0.25 };
    const Tet& t = batch.tets[0];
    const std::array<Vec3, 4> corners{ x[t[0]], x[t[1]], x[t[2]], x[t[3]] };
    TetElasticParameters p;
    p.alphaTildeDeviatoric = batch.deviatoricCompliance[0] / (1e-4);
    p.alphaTildeHydrostatic = batch.hydrostaticCompliance[0] / (1e-4);
    const auto out = projectTetElastic(corners, w, batch.shapeGradients[0], model, batch.restJ[0],
      TetElasticMultipliers::Zero(), p);
    const Mat3 f = [&] {
      Mat3 m = Mat3::Zero();
      for (std::size_t k = 0; k < 4; ++k)
      {
        m += corners[k] * batch.shapeGradients[0][k].transpose();
      }
      return m;
    }();
    const DeviatoricConstraint d = deviatoricConstraint(model, f);
    double linearD = d.value + p.alphaTildeDeviatoric * out.dLambda(0);
    double linearH = f.determinant() - batch.restJ[0] + p.alphaTildeHydrostatic * out.dLambda(1);
    for (std::size_t k = 0; k < 4; ++k)
    {
      linearD += (d.gradient * batch.shapeGradients[0][k]).dot(out.dx[k]);
      linearH += (cofactor(f) * batch.shapeGradients[0][k]).dot(out.dx[k]);
    }
    std::printf("%s: linearized residuals after the projection %.2e, %.2e (before %.2e)\n",
      materialModelName(model), linearD, linearH, out.residual);
    EXPECT_LT(std::abs(linearD), 1e-12 * out.residual) << materialModelName(model);
    EXPECT_LT(std::abs(linearH), 1e-12 * out.residual) << materialModelName(model);
  }
}

namespace
{

/// A bar (2 x 2 x 10 cubic cells of 5 cm) hanging from its top face under gravity.
struct HangingBar
{
  TetMesh mesh = makeTetBox(2, 2, 10, 0.05);
  std::vector<char> top = test::pointsWhere(mesh.points, [](const Vec3& p) { return p.z() > 0.5 - 1e-9; });
  double density = 1000.0, youngsModulus = 1.0e5, poissonRatio = 0.3;
};

std::vector<Vec3> staticSolve(const HangingBar& bar, MaterialModel model)
{
  Body body;
  body.mesh = bar.mesh;
  body.pinned = bar.top;
  body.material.model = model;
  body.material.physical = { bar.youngsModulus, bar.poissonRatio, bar.density, 0.0 };
  body.material.massDistribution = MassDistribution::LumpedVolume;
  return test::staticEquilibrium(body);
}

std::vector<Vec3> xpbdAtRest(const HangingBar& bar, MaterialModel model, int substeps)
{
  Body body = xpbdBody(bar.mesh, model, bar.youngsModulus, bar.poissonRatio, bar.density);
  body.pinned = bar.top;
  PbdSettings settings = xpbdSettings();
  settings.substeps = substeps;
  settings.damping = 5.0; // to rest within the run
  PbdSimulation sim(body, settings);
  sim.advance(2.5);
  return sim.state().positions;
}

} // namespace

TEST(XpbdContinuum, HangingBarRestsWhereTheStaticSolveOfTheSameLawRests)
{
  // The constraints' energy is the law's, so XPBD's rest state is the law's equilibrium up to
  // XPBD's own error: each step rebuilds the elastic force from zero multipliers along the
  // iterates' path, so the force is off by the gradients' change over that path, which shrinks
  // with the square of the substep (Macklin et al. 2019, "Small Steps"). Both laws' constraints
  // vanish at rest (constraint_forms.h), so neither carries a prestress for that error to
  // multiply, and they land alike.
  const HangingBar bar;
  for (MaterialModel model : kModels)
  {
    const std::vector<Vec3> equilibrium = staticSolve(bar, model);
    const double sag = test::maxDistance(equilibrium, bar.mesh.points);
    std::array<double, 3> error{};
    const std::array<int, 3> substeps{ 1, 4, 16 };
    for (std::size_t k = 0; k < 3; ++k)
    {
      error[k] = test::maxDistance(xpbdAtRest(bar, model, substeps[k]), equilibrium) / sag;
      std::printf("%s, 10 iterations x %2d substeps of 1/120 s: %.3e of the sag (%.3e m) from "
        "the static solve\n", materialModelName(model), substeps[k], error[k], sag);
    }
    EXPECT_LT(error[1], error[0] / 4) << materialModelName(model);
    EXPECT_LT(error[2], error[1] / 4) << materialModelName(model);
    EXPECT_LT(error[2], 0.01) << materialModelName(model);
  }
}

TEST(XpbdContinuum, PatchTestConvergesToTheAffineMapAsSubstepsShrink)
{
  // Boundary points held on x = A X + b, the inside started at its rest place, no gravity. The
  // law's equilibrium puts every interior point of the irregular mesh on the map; XPBD's rest
  // state is off it by the error of rebuilding the stress from zero multipliers each step
  // (above), which falls with the square of the substep.
  TetMesh cube = makeTetBox(4, 4, 4, 0.25);
  std::vector<char> boundary(cube.points.size());
  for (std::size_t i = 0; i < cube.points.size(); ++i)
  {
    const Vec3& p = cube.points[i];
    boundary[i] = (p.minCoeff() < 1e-12 || p.maxCoeff() > 1 - 1e-12) ? 1 : 0;
  }
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-0.06, 0.06);
  for (std::size_t i = 0; i < cube.points.size(); ++i)
  {
    if (!boundary[i])
    {
      cube.points[i] += Vec3(u(rng), u(rng), u(rng)); // an irregular mesh
    }
  }
  Mat3 a;
  a << 1.05, 0.02, 0.0, -0.01, 0.97, 0.01, 0.0, 0.02, 1.01;
  const Vec3 b(0.3, -0.2, 0.1);
  for (MaterialModel model : kModels)
  {
    std::array<double, 3> error{};
    const std::array<int, 3> substeps{ 1, 2, 4 };
    for (std::size_t k = 0; k < 3; ++k)
    {
      Body body = xpbdBody(cube, model, 1.0e5, 0.3, 1000.0);
      body.pinned = boundary;
      PbdSettings settings = xpbdSettings();
      settings.gravity = Vec3::Zero();
      settings.damping = 10.0;
      settings.substeps = substeps[k];
      PbdSimulation sim(body, settings);
      DynamicState start = sim.state();
      test::placeOnAffineMap(start.positions, cube.points, boundary, a, b);
      sim.restoreState(start);
      sim.advance(2.0);
      for (std::size_t i = 0; i < cube.points.size(); ++i)
      {
        error[k] = std::max(error[k], (sim.state().positions[i] - (a * cube.points[i] + b)).norm());
      }
      std::printf("%s, %2d substeps: worst interior point %.3e m from the affine map\n",
        materialModelName(model), substeps[k], error[k]);
    }
    std::printf("  measured order in the substep: %.2f, %.2f\n", std::log2(error[0] / error[1]),
      std::log2(error[1] / error[2]));
    EXPECT_LT(error[1], error[0] / 3) << materialModelName(model); // order > 1.58
    EXPECT_LT(error[2], error[1] / 3) << materialModelName(model);
    EXPECT_LT(error[2], 3e-5) << materialModelName(model); // of a 1 m cube strained by ~5 %
  }
}

TEST(XpbdContinuum, CrushedAndInvertedBodyRecoversItsRestShape)
{
  // Both laws push an inverted tet back (the rotation-variant SVD's R stays a rotation, and
  // Stable Neo-Hookean's J - alpha is finite through J = 0): a box crushed to a fifth of its
  // height and turned inside out comes back to its rest volume, tet by tet.
  const TetMesh box = makeTetBox(3, 3, 3, 0.1);
  for (MaterialModel model : kModels)
  {
    PbdSettings settings = xpbdSettings();
    settings.gravity = Vec3::Zero();
    settings.damping = 5.0;
    settings.substeps = 4;
    PbdSimulation sim(xpbdBody(box, model, 1.0e5, 0.3, 1000.0), settings);
    DynamicState start = sim.state();
    for (Vec3& p : start.positions)
    {
      p.z() = -0.2 * p.z(); // crushed and mirrored: every tet inverted
    }
    sim.restoreState(start);
    const std::vector<double> before = sim.tetVolumeRatios();
    ASSERT_LT(*std::max_element(before.begin(), before.end()), 0.0);
    sim.advance(3.0);
    const std::vector<double> after = sim.tetVolumeRatios();
    const auto [low, high] = std::minmax_element(after.begin(), after.end());
    std::printf("%s: volume ratios %.4f .. %.4f after 3 s (all inverted at the start)\n",
      materialModelName(model), *low, *high);
    EXPECT_GT(*low, 0.999) << materialModelName(model);
    EXPECT_LT(*high, 1.001) << materialModelName(model);
  }
}

namespace
{

std::vector<Vec3> landingAt(MaterialModel model, PbdSolver solver, int threads, std::size_t& inverted)
{
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  TetMesh box = makeTetBox(4, 4, 4, 0.05);
  for (Vec3& p : box.points)
  {
    p.z() += 0.1;
  }
  PbdSettings settings = xpbdSettings();
  settings.collisions.mode = CollisionMode::ObstaclesAndBodies;
  settings.floorEnabled = true;
  settings.solver = solver;
  settings.substeps = 2;
  PbdSimulation sim(xpbdBody(box, model, 1.0e5, 0.3, 1000.0), settings);
  inverted = 0;
  for (int frame = 1; frame <= 30; ++frame)
  {
    sim.advance(frame / 30.0);
    const std::vector<double> ratios = sim.tetVolumeRatios();
    inverted = std::max<std::size_t>(inverted, std::count_if(ratios.begin(), ratios.end(), [](double r) { return r <= 0.0; }));
  }
  return sim.state().positions;
}

} // namespace

TEST(XpbdContinuum, LandingIsTheSameAtAnyThreadCountAndInvertsNoTet)
{
  for (MaterialModel model : kModels)
  {
    for (PbdSolver solver : { PbdSolver::GaussSeidel, PbdSolver::ParallelGaussSeidel, PbdSolver::Jacobi })
    {
      std::size_t inverted1 = 0, inverted2 = 0;
      const std::vector<Vec3> one = landingAt(model, solver, 1, inverted1);
      const std::vector<Vec3> two = landingAt(model, solver, 2, inverted2);
      double lowest = 1e300;
      for (const Vec3& p : one)
      {
        lowest = std::min(lowest, p.z());
      }
      std::printf("%s, %s: lowest point %.4f m after 1 s, at most %zu tets inverted in a frame\n",
        materialModelName(model), pbdSolverName(solver, 1.0), lowest, inverted1);
      EXPECT_TRUE(test::bitwiseEqual(one, two)) << materialModelName(model) << " " << pbdSolverName(solver, 1.0);
      EXPECT_EQ(inverted1, 0u) << materialModelName(model) << " " << pbdSolverName(solver, 1.0);
      EXPECT_GT(lowest, -1e-3) << materialModelName(model) << " " << pbdSolverName(solver, 1.0);
      EXPECT_LT(lowest, 0.01) << "it should have landed";
    }
  }
}

TEST(XpbdContinuum, RefusesWhatHasNoMeaningQuotingTheValue)
{
  Body body = xpbdBody(makeTetBox(2, 2, 2, 0.1), MaterialModel::Corotated, 1.0e5, -0.2, 1000.0);
  PbdSettings settings = xpbdSettings();
  EXPECT_NE(refusal(body, settings).find("PoissonRatio -0.2 gives Corotated's hydrostatic constraint a negative"),
    std::string::npos) << refusal(body, settings);
  body.material.model = MaterialModel::StableNeoHookean;
  EXPECT_EQ(refusal(body, settings), ""); // its kH = lambda - mu / 4 >= 0 down to nu = -0.5
  body.material.physical.poissonRatio = -0.7;
  EXPECT_NE(refusal(body, settings).find("PoissonRatio -0.7 gives Stable Neo-Hookean's hydrostatic"),
    std::string::npos) << refusal(body, settings);
  body.material.physical.poissonRatio = 0.5;
  EXPECT_NE(refusal(body, settings).find("0.5"), std::string::npos) << refusal(body, settings);
  body.material.physical.poissonRatio = 0.3;
  settings.formulation = PbdFormulation::Pbd;
  EXPECT_NE(refusal(body, settings).find("needs XPBD"), std::string::npos) << refusal(body, settings);
  settings.formulation = PbdFormulation::Xpbd;
  settings.breakingStrain = 0.4;
  EXPECT_NE(refusal(body, settings).find("BreakingStrain 0.4"), std::string::npos) << refusal(body, settings);
}
