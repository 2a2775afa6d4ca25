#include "softbody/massspring/strain_limit.h"

#include "softbody/common/parallel.h"

namespace softbody
{
namespace
{

/// Pass 1: for every spring longer than maxStretch * l0, the shared correction
/// c = (l - maxStretch l0) n / (w_a + w_b); end a moves by -w_a c, end b by +w_b c, which
/// restores the limit length exactly for this spring alone and keeps its center of mass.
std::size_t springCorrections(const Topology& topology, const ElementConstants& constants,
  const std::vector<double>& w, double maxStretch, const std::vector<Vec3>& x,
  std::vector<Vec3>& correction)
{
  return parallelReduce(
    topology.edges.size(), 2048, std::size_t{ 0 },
    [&](std::size_t e) -> std::size_t {
      const Edge& edge = topology.edges[e];
      const Vec3 d = x[edge.a] - x[edge.b];
      const double length = d.norm();
      const double limit = maxStretch * constants.restLength[e];
      const double wSum = w[edge.a] + w[edge.b];
      if (length <= limit || wSum == 0.0)
      {
        correction[e].setZero();
        return 0;
      }
      correction[e] = ((length - limit) / (length * wSum)) * d;
      return 1;
    },
    [](std::size_t l, std::size_t r) { return l + r; });
}

/// Pass 2: each vertex applies the mean of its springs' requests (averaged Jacobi: the plain
/// sum overshoots where several violated springs meet). One writer per vertex.
void applyMeanCorrections(const Topology& topology, const std::vector<double>& inverseMass,
  const std::vector<Vec3>& edgeCorrection, bool adjustVelocities, double h,
  std::vector<Vec3>& positions, std::vector<Vec3>& velocities)
{
  parallelFor(topology.vertexCount, 1024, [&](std::size_t i) {
    const double wi = inverseMass[i];
    if (wi == 0.0)
    {
      return;
    }
    Vec3 sum = Vec3::Zero();
    int active = 0;
    const Csr& edges = topology.vertexEdges;
    for (std::int32_t k = edges.offsets[i]; k < edges.offsets[i + 1]; ++k)
    {
      const std::int32_t e = edges.items[k];
      const Vec3& c = edgeCorrection[e];
      if (c.isZero(0.0))
      {
        continue;
      }
      sum += (topology.edges[e].a == static_cast<std::int32_t>(i)) ? Vec3(-wi * c) : Vec3(wi * c);
      ++active;
    }
    if (active == 0)
    {
      return;
    }
    const Vec3 delta = sum / active;
    positions[i] += delta;
    if (adjustVelocities)
    {
      velocities[i] += delta / h;
    }
  });
}

} // namespace

std::size_t limitStrain(const Topology& topology, const ElementConstants& constants,
  const std::vector<double>& inverseMass, double maxStretch, int iterations,
  bool adjustVelocities, double h, std::vector<Vec3>& positions, std::vector<Vec3>& velocities,
  StrainLimitScratch& scratch)
{
  scratch.edgeCorrection.resize(topology.edges.size());
  std::size_t firstViolated = 0;
  for (int iteration = 0; iteration < iterations; ++iteration)
  {
    const std::size_t violated = springCorrections(
      topology, constants, inverseMass, maxStretch, positions, scratch.edgeCorrection);
    if (iteration == 0)
    {
      firstViolated = violated;
    }
    if (violated == 0)
    {
      break;
    }
    applyMeanCorrections(topology, inverseMass, scratch.edgeCorrection, adjustVelocities, h,
      positions, velocities);
  }
  return firstViolated;
}

} // namespace softbody
