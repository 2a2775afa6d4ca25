#include "softbody/massspring/mass_spring_forces.h"

#include "softbody/common/parallel.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace softbody
{
namespace
{

// Grain sizes: large enough that a task outweighs TBB's scheduling cost (~1 us).
constexpr std::size_t kElementGrain = 2048;
constexpr std::size_t kVertexGrain = 1024;

/// Pass 1, springs: force on end a of edge e,
///   f_a = -(k (l - l0) + k_d n.(v_a - v_b)) n,  n = (p_a - p_b) / l   (f_b = -f_a).
/// A zero-length spring has no direction; it exerts no force (guarded, never NaN).
void springForces(const Topology& topology, const ElementConstants& c,
  const std::vector<Vec3>& x, const std::vector<Vec3>& v, std::vector<Vec3>& out)
{
  parallelFor(topology.edges.size(), kElementGrain, [&](std::size_t e) {
    const Edge& edge = topology.edges[e];
    const Vec3 d = x[edge.a] - x[edge.b];
    const double length = d.norm();
    if (length < 1e-12 * c.restLength[e])
    {
      out[e].setZero();
      return;
    }
    const Vec3 n = d / length;
    const double stretch = length - c.restLength[e];
    const double stretchRate = n.dot(v[edge.a] - v[edge.b]);
    out[e] = -(c.springStiffness[e] * stretch + c.springDamping[e] * stretchRate) * n;
  });
}

/// Pass 1, volumes: f_i = s dV/dp_i with s = -(k' (V - V0) + k_d' dV/dt), dV/dt = sum g_j.v_j.
void volumeForceScales(const Topology& topology, const ElementConstants& c,
  const std::vector<Vec3>& x, const std::vector<Vec3>& v, std::vector<double>& out)
{
  parallelFor(topology.tets.size(), kElementGrain, [&](std::size_t t) {
    const Tet& tet = topology.tets[t];
    const auto g = tetVolumeGradients(x[tet[0]], x[tet[1]], x[tet[2]], x[tet[3]]);
    const double volume = signedTetVolume(x[tet[0]], x[tet[1]], x[tet[2]], x[tet[3]]);
    double volumeRate = 0.0;
    for (int k = 0; k < 4; ++k)
    {
      volumeRate += g[k].dot(v[tet[k]]);
    }
    out[t] = -(c.volumeStiffness[t] * (volume - c.restVolume[t]) + c.volumeDamping[t] * volumeRate);
  });
}

/// dV/dp of one corner, without computing the other three.
Vec3 cornerVolumeGradient(const std::vector<Vec3>& x, const Tet& tet, int corner)
{
  // Cyclic relabelling keeps the orientation: g_c = (1/6) (p_k - p_j) x (p_l - p_j) with the
  // sign fixed by the parity of the permutation (c, j, k, l).
  static constexpr int kOthers[4][3] = { { 1, 3, 2 }, { 0, 2, 3 }, { 0, 3, 1 }, { 0, 1, 2 } };
  const Vec3& pj = x[tet[kOthers[corner][0]]];
  const Vec3& pk = x[tet[kOthers[corner][1]]];
  const Vec3& pl = x[tet[kOthers[corner][2]]];
  return (pk - pj).cross(pl - pj) / 6.0;
}

} // namespace

void computeInternalForces(const Topology& topology, const ElementConstants& constants,
  const std::vector<Vec3>& positions, const std::vector<Vec3>& velocities, ForceScratch& scratch,
  std::vector<Vec3>& forces)
{
  scratch.springForce.resize(topology.edges.size());
  springForces(topology, constants, positions, velocities, scratch.springForce);
  if (constants.hasVolumeTerm)
  {
    scratch.tetScale.resize(topology.tets.size());
    volumeForceScales(topology, constants, positions, velocities, scratch.tetScale);
  }

  // Pass 2: gather in CSR order (fixed), one writer per vertex.
  forces.resize(topology.vertexCount);
  parallelFor(topology.vertexCount, kVertexGrain, [&](std::size_t i) {
    Vec3 sum = Vec3::Zero();
    const Csr& edges = topology.vertexEdges;
    for (std::int32_t k = edges.offsets[i]; k < edges.offsets[i + 1]; ++k)
    {
      const std::int32_t e = edges.items[k];
      const Vec3& f = scratch.springForce[e];
      sum += (topology.edges[e].a == static_cast<std::int32_t>(i)) ? f : Vec3(-f);
    }
    if (constants.hasVolumeTerm)
    {
      const Csr& corners = topology.vertexTetCorners;
      for (std::int32_t k = corners.offsets[i]; k < corners.offsets[i + 1]; ++k)
      {
        const std::int32_t tetCorner = corners.items[k];
        const std::int32_t t = tetCorner / 4;
        sum += scratch.tetScale[t] * cornerVolumeGradient(positions, topology.tets[t], tetCorner % 4);
      }
    }
    forces[i] = sum;
  });
}

double elasticEnergy(const Topology& topology, const ElementConstants& constants,
  const std::vector<Vec3>& positions)
{
  double energy = 0.0;
  for (std::size_t e = 0; e < topology.edges.size(); ++e)
  {
    const Edge& edge = topology.edges[e];
    const double stretch = (positions[edge.a] - positions[edge.b]).norm() - constants.restLength[e];
    energy += 0.5 * constants.springStiffness[e] * stretch * stretch;
  }
  for (std::size_t t = 0; t < topology.tets.size(); ++t)
  {
    const Tet& tet = topology.tets[t];
    const double dv = signedTetVolume(positions[tet[0]], positions[tet[1]], positions[tet[2]],
                        positions[tet[3]]) - constants.restVolume[t];
    energy += 0.5 * constants.volumeStiffness[t] * dv * dv;
  }
  return energy;
}

double maxStretchRatio(const Topology& topology, const ElementConstants& constants,
  const std::vector<Vec3>& positions)
{
  // max is order-independent, so the parallel reduction is deterministic. A NaN poisons the
  // result on purpose (std::max would silently drop it).
  const double nan = std::numeric_limits<double>::quiet_NaN();
  return parallelReduce(
    topology.edges.size(), kElementGrain, 0.0,
    [&](std::size_t e) {
      const Edge& edge = topology.edges[e];
      return (positions[edge.a] - positions[edge.b]).norm() / constants.restLength[e];
    },
    [nan](double l, double r) { return (std::isnan(l) || std::isnan(r)) ? nan : std::max(l, r); });
}

} // namespace softbody
