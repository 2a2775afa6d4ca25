#include "softbody/massspring/block_sparse_matrix.h"

#include "softbody/common/parallel.h"

namespace softbody
{

BlockSparseMatrix::BlockSparseMatrix(const Topology& topology)
{
  const std::size_t n = topology.vertexCount;
  const Csr& incident = topology.vertexEdges;
  RowStart.resize(n + 1);
  Columns.resize(n + incident.items.size());
  EdgeSlotA.assign(topology.edges.size(), -1);
  EdgeSlotB.assign(topology.edges.size(), -1);
  std::int32_t slot = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    RowStart[i] = slot;
    Columns[slot++] = static_cast<std::int32_t>(i);
    for (std::int32_t k = incident.offsets[i]; k < incident.offsets[i + 1]; ++k)
    {
      const std::int32_t e = incident.items[k];
      const Edge& edge = topology.edges[e];
      const bool rowIsA = edge.a == static_cast<std::int32_t>(i);
      Columns[slot] = rowIsA ? edge.b : edge.a;
      (rowIsA ? EdgeSlotA : EdgeSlotB)[e] = slot;
      ++slot;
    }
  }
  RowStart[n] = slot;
  Blocks.assign(Columns.size(), Mat3::Zero());
  MirrorSlot.resize(Columns.size());
  for (std::size_t i = 0; i < n; ++i)
  {
    MirrorSlot[static_cast<std::size_t>(RowStart[i])] = RowStart[i];
  }
  for (std::size_t e = 0; e < EdgeSlotA.size(); ++e)
  {
    MirrorSlot[static_cast<std::size_t>(EdgeSlotA[e])] = EdgeSlotB[e];
    MirrorSlot[static_cast<std::size_t>(EdgeSlotB[e])] = EdgeSlotA[e];
  }
}

void BlockSparseMatrix::setCoupling(std::vector<double> weights, std::vector<Vec3> entries)
{
  CouplingWeight = std::move(weights);
  CouplingEntry = std::move(entries);
  CouplingProjection.resize(CouplingWeight.size());
}

void BlockSparseMatrix::setZero()
{
  parallelFor(Blocks.size(), 8192, [&](std::size_t k) { Blocks[k].setZero(); });
}

void BlockSparseMatrix::multiply(
  const std::vector<Eigen::Vector3d>& x, std::vector<Eigen::Vector3d>& y) const
{
  y.resize(rowCount());
  parallelFor(rowCount(), 512, [&](std::size_t i) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (std::int32_t k = RowStart[i]; k < RowStart[i + 1]; ++k)
    {
      sum.noalias() += Blocks[k] * x[Columns[k]];
    }
    y[i] = sum;
  });
  if (CouplingWeight.empty())
  {
    return;
  }
  // y_b += sum_a c_ab (w_a c_a . x - w_a c_ab . x_b): the blocks w_a c_ab c_ab^T are in the
  // diagonal already. Two gathers, each row summed in its slots' order.
  parallelFor(rowCount(), 512, [&](std::size_t a) {
    double dot = 0.0;
    for (std::int32_t k = RowStart[a]; k < RowStart[a + 1]; ++k)
    {
      dot += CouplingEntry[k].dot(x[Columns[k]]);
    }
    CouplingProjection[a] = CouplingWeight[a] * dot;
  });
  parallelFor(rowCount(), 512, [&](std::size_t b) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (std::int32_t k = RowStart[b]; k < RowStart[b + 1]; ++k)
    {
      const std::size_t a = static_cast<std::size_t>(Columns[k]);
      const Vec3& entry = CouplingEntry[static_cast<std::size_t>(MirrorSlot[k])]; // c_ab
      sum.noalias() += (CouplingProjection[a] - CouplingWeight[a] * entry.dot(x[b])) * entry;
    }
    y[b] += sum;
  });
}

} // namespace softbody
