#include "softbody/material/mass.h"

#include <algorithm>

namespace softbody
{

PointMasses distributeMass(const Topology& topology, const std::vector<double>& restVolume,
  double totalMass, MassDistribution scheme, double maxInverseMass,
  const std::vector<char>& pinned)
{
  const std::size_t n = topology.vertexCount;
  const Csr& corners = topology.vertexTetCorners;

  // Weight of each point: the mean (thesis) or a quarter of the sum (lumped) of its tets'
  // volumes. Both are then scaled so the weights sum to the total mass.
  std::vector<double> weight(n, 0.0);
  double weightSum = 0.0;
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::int32_t begin = corners.offsets[i], end = corners.offsets[i + 1];
    double volumeSum = 0.0;
    for (std::int32_t k = begin; k < end; ++k)
    {
      volumeSum += restVolume[corners.items[k] / 4];
    }
    if (end > begin)
    {
      weight[i] = scheme == MassDistribution::AverageIncidentVolume ? volumeSum / (end - begin)
                                                                    : volumeSum / 4.0;
    }
    weightSum += weight[i];
  }

  PointMasses result;
  result.mass.resize(n, 0.0);
  result.inverseMass.resize(n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
  {
    if (weight[i] <= 0.0)
    {
      continue; // a point in no tet carries no mass and is not simulated
    }
    double mass = totalMass * weight[i] / weightSum;
    // Truncation: the lightest points limit the stable time step (w = 1/m enters w_max^2);
    // capping w makes them heavier, trading a little mass accuracy for a larger step.
    if (maxInverseMass > 0.0 && 1.0 / mass > maxInverseMass)
    {
      mass = 1.0 / maxInverseMass;
      ++result.truncatedCount;
    }
    result.mass[i] = mass;
    const bool isPinned = !pinned.empty() && pinned[i] != 0;
    result.inverseMass[i] = isPinned ? 0.0 : 1.0 / mass;
    result.totalMass += mass;
  }
  return result;
}

} // namespace softbody
