#include "softbody/material/tet_elastic_forces.h"

#include "softbody/common/parallel.h"

#include <cmath>
#include <limits>

namespace softbody
{
namespace
{

constexpr std::size_t kTetGrain = 1024;

SymmetricTensor symmetricOf(const Mat3& m)
{
  return { m(0, 0), m(1, 1), m(2, 2), m(0, 1), m(1, 2), m(0, 2) };
}

template <IsotropicLaw Law>
void cornerForces(const Topology& topology, const TetElasticConstants& c,
  const std::vector<Vec3>& x, const std::vector<Vec3>& v, TetElasticScratch& scratch)
{
  scratch.cornerForces.resize(topology.tets.size());
  if (c.nodalPressure)
  {
    evaluateNodalPressure(topology, c, x, scratch.nodal);
  }
  parallelFor(topology.tets.size(), kTetGrain, [&](std::size_t t) {
    const Mat3 f = deformationGradient(topology, c, t, x);
    Mat3 stress;
    tetEnergyAndStress<Law>(c, t, f, &scratch.nodal, stress);
    if (c.damped && c.dampingTime[t] > 0.0)
    {
      // The rate of F from the velocities, seen from the current F (the Green strain rate).
      stress += viscousStress(f, deformationGradient(topology, c, t, v), c.linear[t], c.dampingTime[t]);
    }
    for (std::size_t k = 0; k < 4; ++k)
    {
      scratch.cornerForces[t][k] = -c.restVolume[t] * stress * c.shapeGradients[t][k];
    }
  });
}

} // namespace

void computeTetElasticForces(const Topology& topology, const TetElasticConstants& constants,
  const std::vector<Vec3>& x, const std::vector<Vec3>& v, TetElasticScratch& scratch,
  std::vector<Vec3>& forces)
{
  withElasticLaw(constants.model, [&](auto law) {
    cornerForces<decltype(law)>(topology, constants, x, v, scratch);
  });
  forces.resize(x.size());
  parallelFor(x.size(), 4096, [&](std::size_t i) {
    Vec3 sum = Vec3::Zero();
    forEachTetCorner(topology, static_cast<std::int32_t>(i),
      [&](std::size_t t, int corner) { sum += scratch.cornerForces[t][static_cast<std::size_t>(corner)]; });
    forces[i] = sum;
  });
}

double tetElasticEnergy(const Topology& topology, const TetElasticConstants& constants,
  const std::vector<Vec3>& x)
{
  NodalPressureField nodal;
  if (constants.nodalPressure)
  {
    evaluateNodalPressure(topology, constants, x, nodal);
  }
  return withElasticLaw(constants.model, [&](auto law) {
    using Law = decltype(law);
    return parallelSum(topology.tets.size(), [&](std::size_t t) {
      Mat3 stress;
      return constants.restVolume[t] *
        tetEnergyAndStress<Law>(constants, t, deformationGradient(topology, constants, t, x), &nodal, stress);
    }) + nodal.energy;
  });
}

TetStressField tetStressField(const Topology& topology, const TetElasticConstants& constants,
  const std::vector<Vec3>& x)
{
  const std::size_t n = topology.tets.size();
  TetStressField field;
  field.greenStrain.resize(n);
  field.cauchyStress.resize(n);
  field.vonMises.resize(n);
  field.energyDensity.resize(n);
  NodalPressureField nodal;
  if (constants.nodalPressure)
  {
    evaluateNodalPressure(topology, constants, x, nodal);
  }
  withElasticLaw(constants.model, [&](auto law) {
    using Law = decltype(law);
    parallelFor(n, kTetGrain, [&](std::size_t t) {
      const Mat3 f = deformationGradient(topology, constants, t, x);
      Mat3 stress;
      field.greenStrain[t] = symmetricOf(0.5 * (f.transpose() * f - Mat3::Identity()));
      field.energyDensity[t] = tetEnergyAndStress<Law>(constants, t, f, &nodal, stress);
      if (constants.nodalPressure)
      {
        double volumetric = 0.0;
        for (const std::int32_t a : topology.tets[t])
        {
          const double d = nodal.pointRatio[static_cast<std::size_t>(a)] - 1.0;
          volumetric += 0.125 * constants.nodal.lambda[static_cast<std::size_t>(a)] * d * d;
        }
        field.energyDensity[t] += volumetric;
      }
      const double j = f.determinant();
      if (!(j > 0.0))
      {
        // An inverted or flat tet has no Cauchy stress (no current volume to divide by).
        field.cauchyStress[t].fill(std::numeric_limits<double>::quiet_NaN());
        field.vonMises[t] = std::numeric_limits<double>::quiet_NaN();
        return;
      }
      const Mat3 sigma = stress * f.transpose() / j;
      const Mat3 symmetric = 0.5 * (sigma + sigma.transpose());
      field.cauchyStress[t] = symmetricOf(symmetric);
      const Mat3 deviator = symmetric - symmetric.trace() / 3.0 * Mat3::Identity();
      field.vonMises[t] = std::sqrt(1.5 * deviator.squaredNorm());
    });
  });
  return field;
}

} // namespace softbody
