// A symmetric 3x3-block sparse matrix with the sparsity of a tet mesh's vertex graph: one block
// row per vertex holding its diagonal block and one block per incident edge. This is the shape
// of every mass-spring Hessian (each tet's vertex pairs are edges of the mesh), so the pattern
// is built once per body and only the block values change from one Newton iteration to the
// next.
//
// Why not Eigen::SparseMatrix: the scalar CSR stores 9 column indices per block (more bytes
// per product on this memory-bound loop) and its product runs on one thread without OpenMP
// (a design choice, not benchmarked). Rows are written by one task each and summed in a
// fixed order, so the product is the same for any thread count.
#pragma once

#include "softbody/mesh/topology.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace softbody
{

using Mat3 = Eigen::Matrix3d;

class BlockSparseMatrix
{
public:
  BlockSparseMatrix() = default;
  /// The pattern of `topology`'s vertex graph; every block zero.
  explicit BlockSparseMatrix(const Topology& topology);

  std::size_t rowCount() const { return RowStart.empty() ? 0 : RowStart.size() - 1; }
  std::size_t blockCount() const { return Blocks.size(); }

  /// Block slots: the diagonal of row i, and the (a, b) / (b, a) blocks of edge e.
  std::int32_t diagonalSlot(std::size_t i) const { return RowStart[i]; }
  std::int32_t slotInRowA(std::size_t e) const { return EdgeSlotA[e]; }
  std::int32_t slotInRowB(std::size_t e) const { return EdgeSlotB[e]; }
  /// The slot of edge e in row `row` (one of its two end points).
  std::int32_t edgeSlot(std::size_t e, std::int32_t row, const Topology& topology) const
  {
    return topology.edges[e].a == row ? EdgeSlotA[e] : EdgeSlotB[e];
  }

  Mat3& block(std::int32_t slot) { return Blocks[static_cast<std::size_t>(slot)]; }
  const Mat3& block(std::int32_t slot) const { return Blocks[static_cast<std::size_t>(slot)]; }
  std::int32_t rowStart(std::size_t i) const { return RowStart[i]; }
  std::int32_t column(std::int32_t slot) const { return Columns[static_cast<std::size_t>(slot)]; }

  void setZero();
  /// y = A x (with the coupling, when there is one).
  void multiply(const std::vector<Eigen::Vector3d>& x, std::vector<Eigen::Vector3d>& y) const;

  /// A symmetric positive semi-definite term beyond the pattern, sum_a w_a c_a c_a^T, one
  /// vector c_a per row a whose entries lie on row a's columns (c_a at column(slot) is
  /// entries[slot]): the nodal pressure's coupling (material/nodal_pressure.h), which joins
  /// points two edges apart. Its 3x3 diagonal blocks (w_a c_ab c_ab^T at row b) must already be
  /// in the matrix's own blocks, where the preconditioners see them; multiply() adds the rest.
  void setCoupling(std::vector<double> weights, std::vector<Vec3> entries);
  bool hasCoupling() const { return !CouplingWeight.empty(); }
  /// The slot of block (column(slot), row) in row column(slot): the transposed block's.
  std::int32_t mirrorSlot(std::int32_t slot) const { return MirrorSlot[static_cast<std::size_t>(slot)]; }

private:
  std::vector<std::int32_t> RowStart; ///< row i's blocks are [RowStart[i], RowStart[i+1])
  std::vector<std::int32_t> Columns;  ///< block column of each slot (the diagonal first)
  std::vector<Mat3> Blocks;
  std::vector<std::int32_t> EdgeSlotA; ///< slot of block (a, b) of each edge, in row a
  std::vector<std::int32_t> EdgeSlotB; ///< slot of block (b, a), in row b
  std::vector<std::int32_t> MirrorSlot;
  std::vector<double> CouplingWeight;  ///< w_a per row; empty: no coupling
  std::vector<Vec3> CouplingEntry;     ///< c_a's entries, per slot
  mutable std::vector<double> CouplingProjection; ///< w_a c_a . x of the running multiply()
};

} // namespace softbody
