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
}

} // namespace softbody
