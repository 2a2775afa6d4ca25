#include "softbody/stability/element_frequency.h"

#include "softbody/common/parallel.h"

#include <algorithm>
#include <cmath>

namespace softbody
{

double continuumFrequencyBound(const Topology& topology, const TetElasticConstants& constants,
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

} // namespace softbody
