// Continuum bodies in the mass-spring stepper: the patch test under the static solve (a TetGen
// cube, any vertex order, both models), the hanging bar against rho g L^2 / (2E) under
// refinement, a crushed and inverted body that recovers its shape, energy conserved to the
// integrator's order, Projective Dynamics converging to Implicit Euler's step, and the refusals a
// user meets (nu out of range, Raw constants, a static body that nothing holds).
#include "softbody/common/errors.h"
#include "softbody/common/validation.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"
#include "softbody/mesh/tetrahedralize.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <random>

using namespace softbody;

namespace
{

constexpr MaterialModel kContinuumModels[] = { MaterialModel::Corotated,
  MaterialModel::StableNeoHookean };

/// A TetGen mesh of the unit cube with interior points, its vertices shuffled and each tet's
/// corners rotated (orientation kept), so nothing depends on the order a mesher wrote.
TetMesh shuffledTetGenCube()
{
  const std::vector<Vec3> corners{ { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0, 0, 1 },
    { 1, 0, 1 }, { 1, 1, 1 }, { 0, 1, 1 } };
  const std::vector<std::array<std::int32_t, 3>> faces{ { 0, 2, 1 }, { 0, 3, 2 }, { 4, 5, 6 },
    { 4, 6, 7 }, { 0, 1, 5 }, { 0, 5, 4 }, { 1, 2, 6 }, { 1, 6, 5 }, { 2, 3, 7 }, { 2, 7, 6 },
    { 3, 0, 4 }, { 3, 4, 7 } };
  TetrahedralizeOptions options;
  options.maxRadiusEdgeRatio = 1.5;
  options.maxTetVolume = 0.002;
  const TetMesh mesh = tetrahedralizeSurface(corners, faces, options);
  std::vector<std::int32_t> order(mesh.points.size());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), std::mt19937(5));
  TetMesh shuffled;
  shuffled.points.resize(order.size());
  std::vector<std::int32_t> newIndex(order.size());
  for (std::size_t k = 0; k < order.size(); ++k)
  {
    shuffled.points[k] = mesh.points[static_cast<std::size_t>(order[k])];
    newIndex[static_cast<std::size_t>(order[k])] = static_cast<std::int32_t>(k);
  }
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
  {
    Tet tet;
    for (int c = 0; c < 4; ++c)
    {
      tet[static_cast<std::size_t>(c)] = newIndex[static_cast<std::size_t>(mesh.tets[t][static_cast<std::size_t>(c)])];
    }
    if (t % 2)
    {
      tet = { tet[0], tet[2], tet[3], tet[1] }; // an even permutation keeps the orientation
    }
    shuffled.tets.push_back(tet);
  }
  return shuffled;
}

SceneSettings staticScene()
{
  SceneSettings scene;
  scene.integrator = Integrator::Static;
  scene.gravity = Vec3::Zero();
  scene.collisions.mode = CollisionMode::Off;
  scene.implicit.tolerance = 1e-10;
  return scene;
}

/// The first Piola-Kirchhoff stress of each law written directly from its definition
/// (independent of the singular-value form the code uses).
Mat3 closedFormStress(MaterialModel model, const Mat3& f, const LameParameters& linear)
{
  const double j = f.determinant();
  const Mat3 cofactor = j * f.inverse().transpose();
  if (model == MaterialModel::Corotated)
  {
    const Eigen::JacobiSVD<Mat3> svd(f, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Mat3 rotation = svd.matrixU() * svd.matrixV().transpose(); // det F > 0 here
    return 2 * linear.mu * (f - rotation) + linear.lambda * (j - 1) * cofactor;
  }
  const double mu = 4.0 / 3.0 * linear.mu, lambda = linear.lambda + 5.0 / 6.0 * linear.mu;
  const double alpha = 1 + 0.75 * mu / lambda, ic = f.squaredNorm();
  return mu * (1 - 1 / (ic + 1)) * f + lambda * (j - alpha) * cofactor;
}

Body bodyOf(TetMesh mesh, MaterialModel model, double poissonRatio = 0.3)
{
  Body body;
  body.mesh = std::move(mesh);
  body.material.model = model;
  body.material.physical.youngsModulus = 1.0e5;
  body.material.physical.poissonRatio = poissonRatio;
  return body;
}

} // namespace

namespace
{

/// The patch test for the affine map x = a X + b: boundary points held on it, every interior
/// point must land on it, and every tet carry its closed-form stress.
void expectPatchTest(const Mat3& a, VolumetricFormulation volumetric)
{
  const TetMesh cube = shuffledTetGenCube();
  const Vec3 b(0.3, -0.2, 0.1);
  std::vector<char> boundary(cube.points.size());
  std::size_t interior = 0;
  for (std::size_t i = 0; i < cube.points.size(); ++i)
  {
    const Vec3& p = cube.points[i];
    boundary[i] = (p.minCoeff() < 1e-12 || p.maxCoeff() > 1 - 1e-12) ? 1 : 0;
    interior += boundary[i] ? 0 : 1;
  }
  ASSERT_GT(interior, 10u) << "the cube needs interior points to test anything";
  for (MaterialModel model : kContinuumModels)
  {
    Body body = bodyOf(cube, model, 0.3);
    body.material.volumetric = volumetric;
    body.pinned = boundary;
    MassSpringSimulation sim(body, staticScene());
    DynamicState start = sim.state();
    test::placeOnAffineMap(start.positions, cube.points, boundary, a, b);
    sim.restoreState(start);
    sim.advance(0.1);
    double worst = 0.0;
    for (std::size_t i = 0; i < cube.points.size(); ++i)
    {
      worst = std::max(worst, (sim.positions()[i] - (a * cube.points[i] + b)).norm());
    }
    const ImplicitConvergence& newton = *sim.implicitConvergence();
    std::printf("%s, %s: %zu points (%zu inside), %zu tets, worst interior error %.3e m (%d Newton "
                "iterations, relative residual %.1e)\n",
      materialModelName(model), volumetric == VolumetricFormulation::NodalAverage ? "nodal average" : "per tet", cube.points.size(), interior, cube.tets.size(), worst,
      newton.iterations, newton.residual);
    // The large stretch stops at the floor of the line search on Phi: its energy (~1e4 J) is
    // rounded at ~1e-12 J, which a displacement error d changes by K d^2 only once d ~ 1e-9 m.
    const bool smallStrain = (a - Mat3::Identity()).norm() < 0.2;
    EXPECT_LT(worst, smallStrain ? 1e-9 : 1e-8) << materialModelName(model);
    const Mat3 expected = closedFormStress(model, a, lameFromYoung(1.0e5, 0.3)) * a.transpose() / a.determinant();
    const TetStressField field = sim.stressField();
    double worstStress = 0.0;
    for (const SymmetricTensor& sigma : field.cauchyStress)
    {
      const SymmetricTensor want{ expected(0, 0), expected(1, 1), expected(2, 2), expected(0, 1),
        expected(1, 2), expected(0, 2) };
      for (int k = 0; k < 6; ++k)
      {
        worstStress = std::max(worstStress, std::abs(sigma[static_cast<std::size_t>(k)] - want[static_cast<std::size_t>(k)]));
      }
    }
    EXPECT_LT(worstStress, 1e-6 * expected.norm()) << materialModelName(model);
  }
}

} // namespace

TEST(ContinuumSolids, PatchTestReproducesAnAffineDeformationInside)
{
  // A small strain, and a large stretch (80 % along x, the section thinning, a shear): the
  // closed-form stress of each law at that F, in every tet.
  Mat3 small, large;
  small << 1.10, 0.05, 0.00, 0.02, 0.93, 0.03, 0.00, -0.04, 1.06;
  large << 1.80, 0.20, 0.00, 0.00, 0.75, 0.00, 0.00, 0.00, 0.80;
  for (const Mat3& a : { small, large })
  {
    // The nodal average gives every point of an affine map its tets' volume ratio: the same
    // stress, so the patch test holds for it as well.
    for (VolumetricFormulation volumetric : { VolumetricFormulation::PerTet, VolumetricFormulation::NodalAverage })
    {
      expectPatchTest(a, volumetric);
    }
  }
}

TEST(ContinuumSolids, NewtonConvergesQuadraticallyOnTheStaticSolve)
{
  // A soft bar (strain ~10 %) hanging from rest in one static solve. Near the solution Newton
  // takes the law's exact Hessian; with the PSD projection alone the tail is linear (each
  // iteration cuts the residual about 30-fold whatever its size: both laws' twist eigenvalues
  // are 0 at rest, and the projection clamps them in every slightly compressed tet). With
  // rho_k = r_k / r_0, every iteration of the tail (rho_k < 1e-3, before the floor of double
  // precision) must cut the residual by at least sqrt(rho_k): order 1.5 or better, which a
  // linear rate fails within two iterations.
  for (MaterialModel model : kContinuumModels)
  {
    Body body = bodyOf(makeTetBox(2, 2, 10, 0.02), model, 0.0);
    body.material.physical.youngsModulus = 2.0e3;
    body.pinned = test::pointsWhere(body.mesh.points, [](const Vec3& p) { return p.z() > 0.2 - 1e-9; });
    SceneSettings scene = staticScene();
    scene.gravity = Vec3(0, 0, -9.81);
    scene.implicit.tolerance = 1e-12;
    MassSpringSimulation sim(body, scene);
    sim.advance(0.1);
    const std::vector<double>& r = sim.implicitConvergence()->residualHistory;
    ASSERT_GE(r.size(), 4u);
    std::string history;
    for (double value : r)
    {
      history += ' ';
      history += check::quote(value / r.front());
    }
    std::printf("%s: residual over the first%s\n", materialModelName(model), history.c_str());
    int tail = 0;
    for (std::size_t k = 0; k + 1 < r.size(); ++k)
    {
      const double rho = r[k] / r.front(), next = r[k + 1] / r.front();
      if (rho < 1e-3 && next > 1e-12)
      {
        ++tail;
        EXPECT_LT(next / rho, std::sqrt(rho)) << materialModelName(model) << " iteration " << k;
      }
    }
    EXPECT_GE(tail, 2) << materialModelName(model);
  }
}

namespace
{

/// The static equilibrium of `body` under gravity: how far the points `face` selects dropped.
template <class Select>
double staticDrop(const Body& body, Select&& face)
{
  SceneSettings scene = staticScene();
  scene.gravity = Vec3(0, 0, -9.81);
  scene.implicit.tolerance = 1e-9;
  MassSpringSimulation sim(body, scene);
  sim.advance(0.1);
  return test::meanDrop(body.mesh.points, sim.positions(), face);
}

/// Elongation of a bar of square section w = L / 10 hanging from its top face, meshed with
/// `across` cubic cells across and 10 `across` along, from the static solve: the mean drop of
/// the bottom face's points.
double hangingBarElongation(MaterialModel model, double poissonRatio, int across)
{
  const double length = 1.0, width = 0.1;
  Body body = bodyOf(makeTetBox(across, across, 10 * across, width / across), model, poissonRatio);
  body.material.physical.youngsModulus = 1.0e7; // strain ~1e-3: the small-strain regime
  body.material.massDistribution = MassDistribution::LumpedVolume; // the finite-element lumping
  body.pinned = test::pointsWhere(body.mesh.points, [&](const Vec3& p) { return p.z() > length - 1e-9; });
  return staticDrop(body, [](const Vec3& p) { return p.z() < 1e-9; });
}

/// A Fixed condition holding `axes` of the points `select` picks: a roller when one axis.
template <class Select>
Condition roller(const std::string& name, const std::vector<Vec3>& points, std::array<bool, 3> axes, Select&& select)
{
  Condition c;
  c.name = name;
  c.heldAxes = axes;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    if (select(points[i]))
    {
      c.points.push_back(static_cast<std::int32_t>(i));
    }
  }
  return c;
}

/// The same bar supported as uniaxial stress assumes: its top face on rollers (z held), the
/// faces x = 0 and y = 0 on symmetry rollers (x, resp. y, held), so nothing stops the section
/// contracting and no point is held in all three components.
double hangingBarOnRollersElongation(MaterialModel model, double poissonRatio, int across)
{
  const double length = 1.0;
  Body body = bodyOf(makeTetBox(across, across, 10 * across, 0.1 / across), model, poissonRatio);
  body.material.physical.youngsModulus = 1.0e7;
  body.material.massDistribution = MassDistribution::LumpedVolume;
  const std::vector<Vec3>& x = body.mesh.points;
  body.conditions = { roller("top", x, { false, false, true }, [&](const Vec3& p) { return p.z() > length - 1e-9; }),
    roller("x = 0", x, { true, false, false }, [](const Vec3& p) { return p.x() < 1e-9; }),
    roller("y = 0", x, { false, true, false }, [](const Vec3& p) { return p.y() < 1e-9; }) };
  return staticDrop(body, [](const Vec3& p) { return p.z() < 1e-9; });
}

} // namespace

TEST(ContinuumSolids, HangingBarOnSymmetryRollersIsUniaxialAtAnyPoissonRatio)
{
  // With the section free to contract, the continuum's displacement is the uniaxial one
  // (Timoshenko and Goodier's bar under its own weight) at every nu, and the elongation
  // rho g L^2 / (2 E) holds at nu = 0.45 and 0.49 as at 0: what the clamped bar below misses
  // there is the clamp's end effect and locking against it, not the model. What is left is the
  // geometric nonlinearity (strain ~1e-3) and the rollers' flat top (the free bar's top face
  // bulges by nu rho g (x^2 + y^2) / 2E): a few 1e-4. The static solve also takes these rollers
  // as a support that stops every rigid motion, with no point fixed in all three components.
  const double exact = 1100.0 * 9.81 * 1.0 / (2 * 1.0e7);
  for (MaterialModel model : kContinuumModels)
  {
    for (double nu : { 0.0, 0.3, 0.45, 0.49 })
    {
      for (int across : { 1, 2, 4 })
      {
        const double error = hangingBarOnRollersElongation(model, nu, across) / exact - 1;
        std::printf("%s nu %.2f on rollers, %d cells across: relative error %+.3e\n",
          materialModelName(model), nu, across, error);
        EXPECT_LT(std::abs(error), 2e-3) << materialModelName(model) << " nu " << nu << ", " << across << " across";
      }
    }
  }
}

TEST(ContinuumSolids, StaticSolveNamesTheRigidMotionRollersLeaveFree)
{
  // Rollers on x = 0 and y = 0 only: the bar can slide along z, and the refusal says so.
  Body body = bodyOf(makeTetBox(1, 1, 4, 0.1), MaterialModel::Corotated);
  const std::vector<Vec3>& x = body.mesh.points;
  body.conditions = { roller("x = 0", x, { true, false, false }, [](const Vec3& p) { return p.x() < 1e-9; }),
    roller("y = 0", x, { false, true, false }, [](const Vec3& p) { return p.y() < 1e-9; }) };
  const std::string slides = test::refusalOf<MassSpringSimulation>(body, staticScene());
  EXPECT_NE(slides.find("free to move along (0, 0, 1)"), std::string::npos) << slides;
  EXPECT_NE(slides.find("0 fixed points"), std::string::npos) << slides;
}

TEST(ContinuumSolids, HangingBarMatchesUniaxialStressUnderRefinement)
{
  // The bar clamped at its top face. nu = 0: uniaxial stress holds exactly and the continuum
  // elongation is rho g L^2 / (2 E); the finite-element lumping of the mass makes the discrete
  // bar exact too, up to geometric nonlinearity (strain ~1e-3). At nu > 0 the clamp stops the
  // lateral contraction there, so this is no longer the uniaxial problem (the test above is): the error falls at first order (the clamped edges are singular) under uniform
  // refinement (1, 2, 4 cubic cells across: 60 to 3,840 tets), and the Richardson limit differs
  // from the uniaxial value by the continuum's end effect. At nu = 0.45 linear tets lock: the
  // error still falls, slowly (measured order 0.4), and the finest mesh is about 3 % stiff.
  const double exact = 1100.0 * 9.81 * 1.0 / (2 * 1.0e7);
  for (MaterialModel model : kContinuumModels)
  {
    for (double nu : { 0.0, 0.3, 0.45 })
    {
      std::array<double, 3> error{};
      const std::array<int, 3> cells{ 1, 2, 4 };
      for (std::size_t k = 0; k < 3; ++k)
      {
        error[k] = hangingBarElongation(model, nu, cells[k]) / exact - 1;
        std::printf("%s nu %.2f, %d cells across: relative error %+.3e\n",
          materialModelName(model), nu, cells[k], error[k]);
      }
      if (nu == 0.0)
      {
        EXPECT_LT(std::abs(error[2]), 1e-4) << materialModelName(model);
        continue;
      }
      const double ratio = (error[0] - error[1]) / (error[1] - error[2]);
      const double order = std::log2(ratio);
      const double limit = error[2] - (error[1] - error[2]) / (ratio - 1);
      std::printf("  measured order %.2f, extrapolated limit %+.3e\n", order, limit);
      EXPECT_LT(std::abs(error[2]), std::abs(error[1])) << materialModelName(model) << " nu " << nu;
      if (nu < 0.4)
      {
        EXPECT_LT(std::abs(error[2]), 0.01) << materialModelName(model) << " nu " << nu;
        EXPECT_GT(order, 0.8) << materialModelName(model) << " nu " << nu;
        EXPECT_LT(std::abs(limit), 0.01) << materialModelName(model) << " nu " << nu;
      }
      else
      {
        EXPECT_LT(std::abs(error[2]), 0.05) << materialModelName(model) << " nu " << nu;
      }
    }
  }
}

namespace
{

/// Tip deflection of a cantilever of square section h and length 5h clamped at x = 0, sagging
/// under its weight (static solve): the mean drop of the free end's points.
double cantileverTipDeflection(MaterialModel model, double poissonRatio, int cellsAcross,
  bool onRollers, VolumetricFormulation volumetric)
{
  const double h = 0.1, length = 5 * h;
  Body body = bodyOf(makeTetBox(5 * cellsAcross, cellsAcross, cellsAcross, h / cellsAcross), model, poissonRatio);
  body.material.physical.youngsModulus = 1.0e8; // tip deflection ~2e-4 of the length: linear
  body.material.massDistribution = MassDistribution::LumpedVolume;
  body.material.volumetric = volumetric;
  const std::vector<Vec3>& x = body.mesh.points;
  const auto root = [](const Vec3& p) { return p.x() < 1e-9; };
  if (!onRollers)
  {
    body.pinned = test::pointsWhere(x, root);
  }
  else
  {
    // The root section held plane (x) and by its neutral axis (z) and its symmetry line (y):
    // the section is free to contract and expand across, as beam theory has it.
    body.conditions = { roller("root", x, { true, false, false }, root),
      roller("neutral axis", x, { false, false, true },
        [&](const Vec3& p) { return root(p) && std::abs(p.z() - h / 2) < 1e-9; }),
      roller("symmetry line", x, { false, true, false },
        [&](const Vec3& p) { return root(p) && std::abs(p.y() - h / 2) < 1e-9; }) };
  }
  return staticDrop(body, [&](const Vec3& p) { return p.x() > length - 1e-9; });
}

constexpr std::array<int, 3> kCantileverCells{ 2, 4, 8 };

/// The tip deflection's relative error against Timoshenko's beam under its weight,
///   q L^4 / (8 E I) + q L^2 / (2 kappa G A),  q = rho g A,  kappa = 10 (1 + nu) / (12 + 11 nu),
/// on kCantileverCells cells across.
std::array<double, 3> cantileverErrors(MaterialModel model, double poissonRatio, bool onRollers,
  VolumetricFormulation volumetric = VolumetricFormulation::PerTet)
{
  const double h = 0.1, length = 5 * h, e = 1.0e8, rho = 1100.0, g = 9.81, nu = poissonRatio;
  const double area = h * h, inertia = h * h * h * h / 12, q = rho * g * area;
  const double shear = e / (2 * (1 + nu)), kappa = 10 * (1 + nu) / (12 + 11 * nu);
  const double beam = q * std::pow(length, 4) / (8 * e * inertia) + q * length * length / (2 * kappa * shear * area);
  std::array<double, 3> error{};
  for (std::size_t k = 0; k < 3; ++k)
  {
    error[k] = cantileverTipDeflection(model, poissonRatio, kCantileverCells[k], onRollers, volumetric) / beam - 1;
  }
  return error;
}

} // namespace

TEST(ContinuumSolids, CantileverConvergesToTimoshenkoBeamTheory)
{
  // Linear tets are too stiff in bending (they lock) and converge at second order in the cell
  // size, reached only on fine meshes (the measured order grows from about 1.3 to 1.8 over these
  // three). The second-order Richardson limit of the two finest is compared with Timoshenko's
  // beam:
  //   q L^4 / (8 E I) + q L^2 / (2 kappa G A),  q = rho g A,  kappa = 10 (1 + nu) / (12 + 11 nu).
  // At nu > 0 the clamped face also stops the section's lateral contraction there, which beam
  // theory ignores: the 3D body is stiffer by a few percent at this slenderness (L = 5 h).
  for (MaterialModel model : kContinuumModels)
  {
    for (double nu : { 0.0, 0.3 })
    {
      const std::array<double, 3> error = cantileverErrors(model, nu, false);
      for (std::size_t k = 0; k < 3; ++k)
      {
        std::printf("%s nu %.2f, %d cells across: tip deflection error %+.4e\n",
          materialModelName(model), nu, kCantileverCells[k], error[k]);
      }
      const double finestOrder = std::log2(error[1] / error[2]);
      const double limit = error[2] + (error[2] - error[1]) / 3;
      std::printf("  order against beam theory on the two finest %.2f, second-order limit %+.3e\n",
        finestOrder, limit);
      EXPECT_GT(finestOrder, 1.4) << materialModelName(model) << " nu " << nu;
      EXPECT_LT(std::abs(limit), nu == 0.0 ? 0.02 : 0.05) << materialModelName(model) << " nu " << nu;
    }
  }
}

TEST(ContinuumSolids, CantileverOnRollersConvergesToBeamTheoryUntilLinearTetsLock)
{
  // The root held as beam theory holds it (plane, by its neutral axis and symmetry line; the
  // section free to contract and expand): the second-order limit is within 2 % of Timoshenko's
  // beam at nu = 0 and 0.3 as well (the clamped bar above is a few percent stiff at 0.3). At
  // nu = 0.45 linear tets lock in bending: the error still shrinks on every refinement, but the
  // finest mesh (8 cells across, 15,360 tets) is about 13 % stiff and the order is below 1.5,
  // so no limit is claimed there; a locking-free element (F-bar, quadratic tets) would be needed.
  for (MaterialModel model : kContinuumModels)
  {
    for (double nu : { 0.0, 0.3, 0.45 })
    {
      const std::array<double, 3> error = cantileverErrors(model, nu, true);
      const double finestOrder = std::log2(error[1] / error[2]);
      const double limit = error[2] + (error[2] - error[1]) / 3;
      std::printf("%s nu %.2f on rollers: tip errors %+.4e %+.4e %+.4e, order on the two finest %.2f, "
                  "second-order limit %+.3e\n",
        materialModelName(model), nu, error[0], error[1], error[2], finestOrder, limit);
      EXPECT_LT(std::abs(error[1]), std::abs(error[0])) << materialModelName(model) << " nu " << nu;
      EXPECT_LT(std::abs(error[2]), std::abs(error[1])) << materialModelName(model) << " nu " << nu;
      if (nu < 0.4)
      {
        EXPECT_GT(finestOrder, 1.6) << materialModelName(model) << " nu " << nu;
        EXPECT_LT(std::abs(limit), 0.02) << materialModelName(model) << " nu " << nu;
      }
    }
  }
}

TEST(ContinuumSolids, NodalPressureCantileverConvergesToBeamTheoryAtNearIncompressibility)
{
  // The same cantilever on rollers with the volume term averaged at the points: one volume
  // constraint per point instead of one per tet, so the bending the locked tets above resist
  // is free again. The second-order limit of the two finest meshes must be within 2 % of
  // Timoshenko's beam at nu = 0.3, 0.45 and 0.49, at the order of an unlocked element.
  for (MaterialModel model : kContinuumModels)
  {
    for (double nu : { 0.3, 0.45, 0.49 })
    {
      const std::array<double, 3> error = cantileverErrors(model, nu, true, VolumetricFormulation::NodalAverage);
      const double finestOrder = std::log2(error[1] / error[2]);
      const double limit = error[2] + (error[2] - error[1]) / 3;
      std::printf("%s nu %.2f nodal pressure: tip errors %+.4e %+.4e %+.4e, order on the two finest %.2f, "
                  "second-order limit %+.3e\n",
        materialModelName(model), nu, error[0], error[1], error[2], finestOrder, limit);
      EXPECT_LT(std::abs(error[2]), std::abs(error[1])) << materialModelName(model) << " nu " << nu;
      EXPECT_GT(finestOrder, 1.8) << materialModelName(model) << " nu " << nu;
      EXPECT_LT(std::abs(limit), 0.02) << materialModelName(model) << " nu " << nu;
    }
  }
}

TEST(ContinuumSolids, CrushedAndInvertedBodyRecoversItsRestShape)
{
  const TetMesh box = makeTetBox(4, 4, 4, 0.05);
  for (MaterialModel model : kContinuumModels)
  {
    Body body = bodyOf(box, model, 0.3);
    SceneSettings scene;
    scene.integrator = Integrator::ImplicitEuler;
    scene.gravity = Vec3::Zero();
    scene.collisions.mode = CollisionMode::Off;
    scene.timeStep = 1.0 / 120;
    MassSpringSimulation sim(body, scene);
    DynamicState crushed = sim.state();
    for (Vec3& p : crushed.positions)
    {
      p.z() *= -0.2; // every tet flattened to a fifth and turned inside out
    }
    sim.restoreState(crushed);
    const std::vector<double> before = sim.tetVolumeRatios();
    ASSERT_LT(*std::max_element(before.begin(), before.end()), 0.0);
    sim.advance(2.0);
    const std::vector<double> ratios = sim.tetVolumeRatios();
    const auto [lo, hi] = std::minmax_element(ratios.begin(), ratios.end());
    std::printf("%s: volume ratios after 2 s in [%.4f, %.4f]\n", materialModelName(model), *lo, *hi);
    EXPECT_GT(*lo, 0.95) << materialModelName(model);
    EXPECT_LT(*hi, 1.05) << materialModelName(model);
  }
}

TEST(ContinuumSolids, MidpointConservesEnergyToSecondOrder)
{
  // An undamped body released from a stretched shape: the energy error of a second-order
  // integrator falls at least as h^2. (Midpoint, not Verlet: Verlet's velocity is staggered by
  // half a step, so the energy computed from it is only first-order accurate.) The nodal
  // average's forces are its energy's gradient as well: the same order at nu = 0.45.
  for (VolumetricFormulation volumetric : { VolumetricFormulation::PerTet, VolumetricFormulation::NodalAverage })
  {
    for (MaterialModel model : kContinuumModels)
    {
      const bool nodal = volumetric == VolumetricFormulation::NodalAverage;
      double previous = 0.0;
      for (double h : { 1e-4, 5e-5 })
      {
        Body body = bodyOf(makeTetBox(3, 3, 3, 0.05), model, nodal ? 0.45 : 0.3);
        body.material.physical.dampingTime = 0.0;
        body.material.volumetric = volumetric;
        SceneSettings scene;
        scene.integrator = Integrator::Midpoint;
        scene.gravity = Vec3::Zero();
        scene.collisions.mode = CollisionMode::Off;
        scene.timeStep = h;
        MassSpringSimulation sim(body, scene);
        DynamicState stretched = sim.state();
        for (Vec3& p : stretched.positions)
        {
          p.x() *= 1.1;
        }
        sim.restoreState(stretched);
        const double e0 = sim.mechanicalEnergy();
        double worst = 0.0;
        for (int frame = 1; frame <= 20; ++frame)
        {
          sim.advance(frame * 0.001);
          worst = std::max(worst, std::abs(sim.mechanicalEnergy() / e0 - 1));
        }
        std::printf("%s%s h %.0e: largest relative energy error %.3e\n", materialModelName(model),
          nodal ? " (nodal average, nu 0.45)" : "", h, worst);
        if (previous > 0.0)
        {
          const double order = std::log2(previous / worst);
          std::printf("  measured order %.2f\n", order);
          EXPECT_GT(order, 1.7) << materialModelName(model);
        }
        EXPECT_LT(worst, 1e-2) << materialModelName(model);
        previous = worst;
      }
    }
  }
}

TEST(ContinuumSolids, ProjectiveDynamicsConvergesToImplicitEulersStep)
{
  // Both solve the same backward-Euler step of the model: with more iterations Projective
  // Dynamics' answer comes to Newton's, to the precision Newton's own answer has.
  for (MaterialModel model : kContinuumModels)
  {
    Body body = bodyOf(makeTetBox(3, 3, 3, 0.05), model, 0.3);
    DynamicState start;
    start.positions = test::jitter(body.mesh.points, 0.005);
    start.velocities = test::randomVectors(start.positions.size(), 0.5);
    SceneSettings scene;
    scene.collisions.mode = CollisionMode::Off;
    scene.timeStep = 1.0 / 60.0;
    scene.integrator = Integrator::ImplicitEuler;
    scene.implicit.tolerance = 1e-7;
    MassSpringSimulation newton(body, scene);
    newton.restoreState(start);
    newton.advance(scene.timeStep);
    ASSERT_TRUE(newton.implicitConvergence()->converged) << materialModelName(model);
    scene.integrator = Integrator::ProjectiveDynamics;
    scene.implicit.tolerance = 0.0; // a fixed number of iterations
    double previous = 1e300;
    for (int iterations : { 2, 8, 32, 128 })
    {
      scene.implicit.maxIterations = iterations;
      MassSpringSimulation pd(body, scene);
      pd.restoreState(start);
      pd.advance(scene.timeStep);
      const double error = test::maxDistance(pd.positions(), newton.positions());
      std::printf("%s: Projective Dynamics, %3d iterations: %.3e m from Newton's step\n",
        materialModelName(model), iterations, error);
      EXPECT_LE(error, previous) << materialModelName(model) << " " << iterations;
      previous = error;
    }
    EXPECT_LT(previous, 1e-8) << materialModelName(model);
  }
}

namespace
{

std::string refusal(Body body, SceneSettings scene)
{
  try
  {
    MassSpringSimulation sim(std::move(body), scene);
  }
  catch (const InvalidInputError& error)
  {
    return error.what();
  }
  return {};
}

} // namespace

TEST(ContinuumSolids, RefusesWhatHasNoMeaningQuotingTheValue)
{
  const TetMesh box = makeTetBox(2, 2, 2, 0.1);
  SceneSettings scene;
  for (double nu : { 0.5, -1.0, 0.7 })
  {
    const std::string message = refusal(bodyOf(box, MaterialModel::Corotated, nu), scene);
    EXPECT_NE(message.find("PoissonRatio"), std::string::npos) << message;
    EXPECT_NE(message.find(check::quote(nu)), std::string::npos) << message;
  }
  Body raw = bodyOf(box, MaterialModel::StableNeoHookean);
  raw.material.mode = MaterialMode::Raw;
  EXPECT_NE(refusal(raw, scene).find("MaterialMode to Physical"), std::string::npos);
  const std::string unheld = refusal(bodyOf(box, MaterialModel::Corotated), staticScene());
  EXPECT_NE(unheld.find("0 fixed points"), std::string::npos) << unheld;
  Body onALine = bodyOf(box, MaterialModel::Corotated);
  onALine.pinned.assign(box.points.size(), 0);
  for (std::size_t i = 0; i < box.points.size(); ++i)
  {
    onALine.pinned[i] = box.points[i].y() < 1e-9 && box.points[i].z() < 1e-9 ? 1 : 0;
  }
  const std::string turns = refusal(onALine, staticScene());
  EXPECT_NE(turns.find("free to turn about the line along (1, 0, 0)"), std::string::npos) << turns;
}

TEST(ContinuumSolids, NegativePoissonRatioIsTakenAsGivenAndNearIncompressibleIsWarned)
{
  const TetMesh box = makeTetBox(2, 2, 2, 0.1);
  SceneSettings scene;
  scene.collisions.mode = CollisionMode::Off;
  MassSpringSimulation auxetic(bodyOf(box, MaterialModel::Corotated, -0.4), scene);
  EXPECT_TRUE(auxetic.warnings().empty()) << auxetic.warnings().front();
  MassSpringSimulation rubber(bodyOf(box, MaterialModel::StableNeoHookean, 0.49), scene);
  ASSERT_EQ(rubber.warnings().size(), 1u);
  EXPECT_NE(rubber.warnings().front().find("PoissonRatio 0.49"), std::string::npos);
  EXPECT_NE(rubber.warnings().front().find("lock"), std::string::npos);
  EXPECT_NE(rubber.warnings().front().find("Nodal Average"), std::string::npos) << "the remedy";
  Body averaged = bodyOf(box, MaterialModel::StableNeoHookean, 0.49);
  averaged.material.volumetric = VolumetricFormulation::NodalAverage;
  MassSpringSimulation unlocked(averaged, scene);
  EXPECT_TRUE(unlocked.warnings().empty()) << unlocked.warnings().front();
}
