// The nodal-averaged pressure (material/nodal_pressure.h) as the implicit integrators see it:
// its energy's gradient and exact Hessian (the coupling product included) against finite
// differences on a jittered, non-affinely deformed body; an affine deformation has the per-tet
// energy exactly; the average never stores more volumetric energy than the tets alone (Jensen);
// and the refusals of the pairings that cannot hold it.
#include "softbody/common/errors.h"
#include "softbody/massspring/block_sparse_matrix.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/massspring/model_potential_factory.h"
#include "softbody/material/mass.h"
#include "softbody/material/tet_elastic_forces.h"
#include "softbody/mesh/mesh_generators.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace softbody;

namespace
{

constexpr MaterialModel kContinuumModels[] = { MaterialModel::Corotated,
  MaterialModel::StableNeoHookean };

MaterialSettings nearlyIncompressible(MaterialModel model, VolumetricFormulation volumetric)
{
  MaterialSettings material;
  material.model = model;
  material.volumetric = volumetric;
  material.physical.youngsModulus = 1.0e5;
  material.physical.poissonRatio = 0.45;
  return material;
}

/// A box of 3 x 3 x 3 cells with its rest points jittered (tets of many shapes) and the
/// constants of `material` on it, undamped (the energy alone).
struct JitteredBody
{
  TetMesh mesh;
  Topology topology;
  TetElasticConstants constants;
  explicit JitteredBody(const MaterialSettings& material)
    : mesh(makeTetBox(3, 3, 3, 0.1))
  {
    mesh.points = test::jitter(mesh.points, 0.012, 11);
    topology = buildTopology(mesh.points.size(), mesh.tets);
    std::vector<std::string> warnings;
    constants = computeTetElasticConstants(topology, mesh.points, material, warnings);
    constants.damped = false;
  }
};

std::vector<Vec3> randomField(std::size_t n, double amplitude, unsigned seed)
{
  return test::jitter(std::vector<Vec3>(n, Vec3::Zero()), amplitude, seed);
}

std::vector<Vec3> plus(const std::vector<Vec3>& x, const std::vector<Vec3>& d, double scale)
{
  std::vector<Vec3> y(x.size());
  for (std::size_t i = 0; i < x.size(); ++i)
  {
    y[i] = x[i] + scale * d[i];
  }
  return y;
}

double dot(const std::vector<Vec3>& a, const std::vector<Vec3>& b)
{
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    sum += a[i].dot(b[i]);
  }
  return sum;
}

} // namespace

TEST(NodalPressure, GradientAndExactHessianAreTheEnergysDerivatives)
{
  // A deformation of ~5 % strain that differs from tet to tet, so every point's averaged
  // volume ratio differs from its tets' own and the coupling between points two edges apart
  // matters. The static potential (no inertia, no gravity): Phi is the elastic energy alone.
  // Every fifth point is held: a held point's volume term still couples its free neighbours,
  // so the free rows must match the derivatives of Phi over the free points alone.
  for (MaterialModel model : kContinuumModels)
  {
    const JitteredBody body(nearlyIncompressible(model, VolumetricFormulation::NodalAverage));
    const std::size_t n = body.mesh.points.size();
    std::vector<char> held(n, 0);
    for (std::size_t i = 0; i < n; i += 5)
    {
      held[i] = 1;
    }
    const PointMasses masses = distributeMass(body.topology, body.constants.restVolume, 1.0,
      MassDistribution::LumpedVolume, 0.0, held);
    const BodyElements elements{ model, nullptr, &body.constants };
    auto potential = makeIncrementalPotential(body.topology, elements, masses, Vec3::Zero());
    potential->makeStatic();
    potential->beginStep(body.mesh.points, std::vector<Vec3>(n, Vec3::Zero()), 1.0);
    const std::vector<Vec3> x = plus(body.mesh.points, randomField(n, 0.005, 3), 1.0);
    std::vector<Vec3> gradient;
    potential->evaluate(x, gradient);
    BlockSparseMatrix hessian(body.topology);
    ASSERT_TRUE(potential->hasExactHessian());
    potential->assembleHessian(x, hessian, true);
    ASSERT_TRUE(hessian.hasCoupling()) << "the nodal pressure must couple points beyond the blocks";

    // The directional derivative of Phi along d, and of its gradient, by central differences.
    std::vector<Vec3> d = randomField(n, 1.0, 17);
    for (std::size_t i = 0; i < n; ++i)
    {
      d[i] = held[i] ? Vec3::Zero() : d[i];
    }
    const double eps = 1e-7;
    std::vector<Vec3> gPlus, gMinus;
    const double ePlus = potential->evaluate(plus(x, d, eps), gPlus);
    const double eMinus = potential->evaluate(plus(x, d, -eps), gMinus);
    const double numericSlope = (ePlus - eMinus) / (2 * eps);
    EXPECT_NEAR(dot(gradient, d), numericSlope, 1e-6 * std::abs(numericSlope)) << materialModelName(model);

    std::vector<Vec3> product(n);
    hessian.multiply(d, product);
    double worst = 0.0, scale = 0.0;
    for (std::size_t i = 0; i < n; ++i)
    {
      if (held[i])
      {
        continue; // its row is the identity's, its gradient zero
      }
      const Vec3 numeric = (gPlus[i] - gMinus[i]) / (2 * eps);
      worst = std::max(worst, (product[i] - numeric).cwiseAbs().maxCoeff());
      scale = std::max(scale, numeric.cwiseAbs().maxCoeff());
    }
    std::printf("%s: slope %.6e (numeric %.6e), worst Hessian-product entry error %.2e of %.2e\n",
      materialModelName(model), dot(gradient, d), numericSlope, worst, scale);
    EXPECT_LT(worst, 1e-5 * scale) << materialModelName(model);

    // The explicit integrators' forces are the same energy's negative gradient.
    TetElasticScratch scratch;
    std::vector<Vec3> forces;
    computeTetElasticForces(body.topology, body.constants, x, std::vector<Vec3>(n, Vec3::Zero()), scratch, forces);
    double forceError = 0.0, forceScale = 0.0;
    for (std::size_t i = 0; i < n; ++i)
    {
      if (held[i])
      {
        continue;
      }
      forceError = std::max(forceError, (forces[i] + gradient[i]).norm());
      forceScale = std::max(forceScale, gradient[i].norm());
    }
    EXPECT_LT(forceError, 1e-9 * forceScale) << materialModelName(model);
  }
}

TEST(NodalPressure, AnAffineDeformationStoresThePerTetEnergyAndOthersNoMore)
{
  // Under an affine map every tet and every point has the same volume ratio, so the two
  // formulations agree (the patch test rests on this); under any other deformation the
  // points' average squares a mean where the tets square each value: never more energy.
  Mat3 a;
  a << 1.05, 0.02, 0.0, -0.01, 0.96, 0.03, 0.0, 0.0, 1.08;
  for (MaterialModel model : kContinuumModels)
  {
    const JitteredBody perTet(nearlyIncompressible(model, VolumetricFormulation::PerTet));
    const JitteredBody nodal(nearlyIncompressible(model, VolumetricFormulation::NodalAverage));
    std::vector<Vec3> affine(perTet.mesh.points.size());
    for (std::size_t i = 0; i < affine.size(); ++i)
    {
      affine[i] = a * perTet.mesh.points[i] + Vec3(0.2, 0.0, -0.1);
    }
    const double eTet = tetElasticEnergy(perTet.topology, perTet.constants, affine);
    const double eNodal = tetElasticEnergy(nodal.topology, nodal.constants, affine);
    EXPECT_NEAR(eNodal, eTet, 1e-12 * eTet) << materialModelName(model);
    for (unsigned seed : { 1u, 2u, 3u })
    {
      const std::vector<Vec3> x = plus(affine, randomField(affine.size(), 0.004, seed), 1.0);
      EXPECT_LE(tetElasticEnergy(nodal.topology, nodal.constants, x),
        tetElasticEnergy(perTet.topology, perTet.constants, x))
        << materialModelName(model) << " seed " << seed;
    }
  }
}

TEST(NodalPressure, RefusesThePairingsThatCannotHoldItNamingTheOneThatWorks)
{
  const auto bodyWith = [](MaterialModel model, double nu) {
    Body body;
    body.mesh = makeTetBox(2, 2, 2, 0.1);
    body.material = nearlyIncompressible(model, VolumetricFormulation::NodalAverage);
    body.material.physical.poissonRatio = nu;
    return body;
  };
  const auto refusal = [](const Body& body, Integrator integrator) {
    SceneSettings scene;
    scene.integrator = integrator;
    try
    {
      MassSpringSimulation sim(body, scene);
    }
    catch (const InvalidInputError& e)
    {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string network = refusal(bodyWith(MaterialModel::SpringNetwork, 0.3), Integrator::ImplicitEuler);
  EXPECT_NE(network.find("Spring Network"), std::string::npos) << network;
  const std::string auxetic = refusal(bodyWith(MaterialModel::Corotated, -0.2), Integrator::ImplicitEuler);
  EXPECT_NE(auxetic.find("-0.2"), std::string::npos) << auxetic;
  EXPECT_NE(auxetic.find("Per Tet"), std::string::npos) << auxetic;
  const std::string pd = refusal(bodyWith(MaterialModel::Corotated, 0.45), Integrator::ProjectiveDynamics);
  EXPECT_NE(pd.find("Implicit Euler"), std::string::npos) << pd;
  EXPECT_TRUE(refusal(bodyWith(MaterialModel::StableNeoHookean, 0.45), Integrator::ImplicitEuler).empty());
}
