#include "softbody/stability/element_frequency.h"

#include "softbody/common/parallel.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace softbody
{
namespace
{

constexpr std::size_t kGrain = 2048;

/// y = D K D x, D = M^-1/2, K the linear-elasticity stiffness of the tets at rest: a pass over
/// the tets (each its four corner forces), then a gather per vertex in the topology's corner
/// order, so the product is the same bit for bit at any thread count.
class ScaledRestElasticity
{
public:
  ScaledRestElasticity(const Topology& topology, const TetElasticConstants& constants,
    const std::vector<double>& inverseMass)
    : Topology_(topology)
    , Constants(constants)
    , Scale(topology.vertexCount)
    , Scaled(topology.vertexCount)
    , CornerForce(topology.tets.size())
  {
    parallelFor(topology.vertexCount, kGrain, [&](std::size_t i) { Scale[i] = std::sqrt(inverseMass[i]); });
  }

  void apply(const std::vector<Vec3>& x, std::vector<Vec3>& y)
  {
    const Topology& topology = Topology_;
    parallelFor(topology.vertexCount, kGrain, [&](std::size_t i) { Scaled[i] = Scale[i] * x[i]; });
    parallelFor(topology.tets.size(), kGrain, [&](std::size_t t) {
      const Tet& tet = topology.tets[t];
      const std::array<Vec3, 4>& g = Constants.shapeGradients[t];
      Mat3 gradient = Scaled[tet[0]] * g[0].transpose();
      for (int k = 1; k < 4; ++k)
      {
        gradient.noalias() += Scaled[tet[k]] * g[static_cast<std::size_t>(k)].transpose();
      }
      const Mat3 strain = 0.5 * (gradient + gradient.transpose());
      const LameParameters& lame = Constants.linear[t];
      const Mat3 stress = 2.0 * lame.mu * strain + lame.lambda * strain.trace() * Mat3::Identity();
      for (int k = 0; k < 4; ++k)
      {
        CornerForce[t][static_cast<std::size_t>(k)] = Constants.restVolume[t] * (stress * g[static_cast<std::size_t>(k)]);
      }
    });
    y.resize(topology.vertexCount);
    const Csr& corners = topology.vertexTetCorners;
    parallelFor(topology.vertexCount, kGrain, [&](std::size_t i) {
      Vec3 sum = Vec3::Zero();
      for (std::int32_t k = corners.offsets[i]; k < corners.offsets[i + 1]; ++k)
      {
        const std::int32_t corner = corners.items[k];
        sum += CornerForce[static_cast<std::size_t>(corner / 4)][static_cast<std::size_t>(corner % 4)];
      }
      y[i] = Scale[i] * sum;
    });
  }

private:
  const Topology& Topology_;
  const TetElasticConstants& Constants;
  std::vector<double> Scale;                    ///< sqrt(w_i), 0 for pinned points
  std::vector<Vec3> Scaled;                     ///< scratch: D x
  std::vector<std::array<Vec3, 4>> CornerForce; ///< scratch of the tet pass
};

} // namespace

double continuumGershgorinBound(const Topology& topology, const TetElasticConstants& constants,
  const std::vector<double>& inverseMass, const std::vector<Vec3>& restPositions)
{
  // Every continuum law has the same rest stiffness (the linear one), so either family bounds it.
  const TetElasticFamily<CorotatedLaw> tets(topology, constants);
  const double bound = parallelReduce(
    topology.vertexCount, 1024, 0.0,
    [&](std::size_t i) {
      double row = 0.0;
      tets.forEachCorner(static_cast<std::int32_t>(i),
        [&](std::size_t t, int corner) { row += tets.stiffnessBound(t, corner, restPositions); });
      return inverseMass[i] * row;
    },
    [](double a, double b) { return std::max(a, b); });
  return std::sqrt(bound);
}

LanczosFrequency continuumLanczosEstimate(const Topology& topology, const TetElasticConstants& constants,
  const std::vector<double>& inverseMass, const std::vector<Vec3>& restPositions, int iterations)
{
  if (topology.vertexCount == 0 || iterations < 1)
  {
    return {};
  }
  ScaledRestElasticity stiffness(topology, constants, inverseMass);
  return lanczosFrequencyEstimate(
    [&](const std::vector<Vec3>& x, std::vector<Vec3>& y) { stiffness.apply(x, y); }, inverseMass, restPositions,
    iterations);
}

double continuumFrequencyBound(const Topology& topology, const TetElasticConstants& constants,
  const std::vector<double>& inverseMass, const std::vector<Vec3>& restPositions)
{
  const double gershgorin = continuumGershgorinBound(topology, constants, inverseMass, restPositions);
  const LanczosFrequency lanczos =
    continuumLanczosEstimate(topology, constants, inverseMass, restPositions, kFrequencyLanczosSteps);
  return lanczos.upperOmega > 0.0 ? std::min(gershgorin, kDeformationMargin * lanczos.upperOmega) : gershgorin;
}

double modelFrequencyBound(MaterialModel model, const Topology& topology, const ElementConstants& network,
  const TetElasticConstants& tets, const std::vector<double>& inverseMass, const std::vector<Vec3>& restPositions)
{
  return isContinuum(model) ? continuumFrequencyBound(topology, tets, inverseMass, restPositions)
                            : highestFrequencyBound(topology, network, inverseMass, restPositions);
}

} // namespace softbody
