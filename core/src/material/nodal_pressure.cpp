#include "softbody/material/nodal_pressure.h"

#include "softbody/common/parallel.h"
#include "softbody/massspring/block_sparse_matrix.h"
#include "softbody/material/tet_corners.h"
#include "softbody/material/tet_elasticity.h"

namespace softbody
{
namespace
{

constexpr std::size_t kTetGrain = 1024;
constexpr std::size_t kPointGrain = 512;

} // namespace

NodalPressureConstants computeNodalPressureConstants(const Topology& topology,
  const std::vector<double>& restVolume, const std::vector<double>& tetLambda)
{
  NodalPressureConstants nodal;
  nodal.volume.assign(topology.vertexCount, 0.0);
  nodal.lambda.assign(topology.vertexCount, 0.0);
  parallelFor(topology.vertexCount, kPointGrain, [&](std::size_t a) {
    double volume = 0.0, weighted = 0.0;
    forEachTetCorner(topology, static_cast<std::int32_t>(a), [&](std::size_t t, int) {
      volume += 0.25 * restVolume[t];
      weighted += 0.25 * restVolume[t] * tetLambda[t];
    });
    nodal.volume[a] = volume;
    nodal.lambda[a] = volume > 0.0 ? weighted / volume : 0.0;
  });
  return nodal;
}

void evaluateNodalPressure(const Topology& topology, const TetElasticConstants& c,
  const std::vector<Vec3>& x, NodalPressureField& field)
{
  const std::size_t tets = topology.tets.size(), points = topology.vertexCount;
  field.tetRatio.resize(tets);
  field.pointRatio.resize(points);
  field.tetPressure.resize(tets);
  parallelFor(tets, kTetGrain,
    [&](std::size_t t) { field.tetRatio[t] = deformationGradient(topology, c, t, x).determinant(); });
  parallelFor(points, kPointGrain, [&](std::size_t a) {
    const double volume = c.nodal.volume[a];
    if (!(volume > 0.0))
    {
      field.pointRatio[a] = 1.0;
      return;
    }
    double current = 0.0;
    forEachTetCorner(topology, static_cast<std::int32_t>(a),
      [&](std::size_t t, int) { current += 0.25 * c.restVolume[t] * field.tetRatio[t]; });
    field.pointRatio[a] = current / volume;
  });
  // p_a = lambda_a (Jbar_a - 1), formed at each corner rather than kept per point: four
  // multiply-adds per tet instead of a point-sized buffer per call.
  const auto pressureAt = [&](std::int32_t a) {
    return c.nodal.lambda[static_cast<std::size_t>(a)] * (field.pointRatio[static_cast<std::size_t>(a)] - 1.0);
  };
  parallelFor(tets, kTetGrain, [&](std::size_t t) {
    const Tet& tet = topology.tets[t];
    field.tetPressure[t] = 0.25 * (pressureAt(tet[0]) + pressureAt(tet[1]) + pressureAt(tet[2]) + pressureAt(tet[3]));
  });
  field.energy = parallelSum(points, [&](std::size_t a) {
    const double d = field.pointRatio[a] - 1.0;
    return 0.5 * c.nodal.volume[a] * c.nodal.lambda[a] * d * d;
  });
}

void addNodalPressureCoupling(const Topology& topology, const TetElasticConstants& c,
  const std::vector<Vec3>& x, const std::vector<char>& active, BlockSparseMatrix& hessian)
{
  const std::size_t points = topology.vertexCount;
  // grad_b Jbar_a = sum over a's tets t holding b of V0_t cof(F_t) g_tb / (4 V_a), written on
  // row a's slots (every corner of a's tets is a or an edge neighbour of a).
  std::vector<Vec3> entries(hessian.blockCount(), Vec3::Zero());
  std::vector<double> weights(points, 0.0);
  // Every point's volume term, a held point's too: its Jbar still moves with its free
  // neighbours, so its w_a c_a c_a^T couples them (only the held rows and columns drop out).
  parallelFor(points, kPointGrain, [&](std::size_t a) {
    const double volume = c.nodal.volume[a];
    if (!(volume > 0.0))
    {
      return;
    }
    weights[a] = volume * c.nodal.lambda[a];
    forEachTetCorner(topology, static_cast<std::int32_t>(a), [&](std::size_t t, int corner) {
      const Mat3 cofactor = cofactorOf(deformationGradient(topology, c, t, x));
      const double scale = 0.25 * c.restVolume[t] / volume;
      for (int k = 0; k < 4; ++k)
      {
        const std::int32_t slot = k == corner
          ? hessian.diagonalSlot(a)
          : hessian.edgeSlot(static_cast<std::size_t>(tetEdgeBetween(topology, t, corner, k)),
              static_cast<std::int32_t>(a), topology);
        entries[static_cast<std::size_t>(slot)] += scale * cofactor * c.shapeGradients[t][static_cast<std::size_t>(k)];
      }
    });
  });
  // The diagonal blocks sum_a w_a c_ab c_ab^T of each active row b, in its slots' order.
  parallelFor(points, kPointGrain, [&](std::size_t b) {
    if (!active[b])
    {
      return;
    }
    Mat3& diagonal = hessian.block(hessian.diagonalSlot(b));
    for (std::int32_t k = hessian.rowStart(b); k < hessian.rowStart(b + 1); ++k)
    {
      const std::size_t a = static_cast<std::size_t>(hessian.column(k));
      const Vec3& entry = entries[static_cast<std::size_t>(hessian.mirrorSlot(k))];
      diagonal.noalias() += weights[a] * entry * entry.transpose();
    }
  });
  // Inactive rows and columns take no part: the solver filters them, and their entries are
  // dropped so the product leaves them alone.
  parallelFor(points, kPointGrain, [&](std::size_t a) {
    for (std::int32_t k = hessian.rowStart(a); k < hessian.rowStart(a + 1); ++k)
    {
      if (!active[static_cast<std::size_t>(hessian.column(k))])
      {
        entries[static_cast<std::size_t>(k)].setZero();
      }
    }
  });
  hessian.setCoupling(std::move(weights), std::move(entries));
}

} // namespace softbody
