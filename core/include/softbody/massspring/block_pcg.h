// Conjugate gradients on a BlockSparseMatrix, preconditioned by the inverses of its 3x3
// diagonal blocks (block Jacobi: each vertex's own mass and stiffness, in every direction), or
// by a PcgPreconditioner that sees more of the matrix (coordinate_preconditioner.h).
// The motion filter restricts the solution: pinned points stay zero, points on the floor move
// only along it (the filtered PCG of Baraff and Witkin 1998). Dot products use
// parallelSum, so the iterates are the same for any thread count.
#pragma once

#include "softbody/massspring/block_sparse_matrix.h"
#include "softbody/massspring/motion_filter.h"

#include <vector>

namespace softbody
{

struct PcgResult
{
  int iterations = 0;
  double relativeResidual = 0.0; ///< ||b - A x|| / ||b|| at exit
  bool converged = false;
  bool indefinite = false; ///< stopped at a direction of non-positive curvature
};

/// Work arrays reused across solves (no allocation in the step loop).
struct PcgScratch
{
  std::vector<Mat3> inverseDiagonal;
  std::vector<Eigen::Vector3d> residual, preconditioned, direction, product;
};

/// z = P^-1 r for a symmetric positive definite P; the solver filters z afterwards.
class PcgPreconditioner
{
public:
  virtual ~PcgPreconditioner() = default;
  virtual void apply(const std::vector<Eigen::Vector3d>& r, std::vector<Eigen::Vector3d>& z) = 0;
};

/// Solves S A S x = S b for a symmetric positive definite A, S the filter, starting from x = 0,
/// until ||S (b - A x)|| <= relativeTolerance ||S b|| or maxIterations, preconditioned by
/// S P^-1 S (block Jacobi when `preconditioner` is null).
PcgResult solveBlockPcg(const BlockSparseMatrix& A, const MotionFilter& filter,
  const std::vector<Eigen::Vector3d>& b, double relativeTolerance, int maxIterations,
  std::vector<Eigen::Vector3d>& x, PcgScratch& scratch,
  PcgPreconditioner* preconditioner = nullptr);

} // namespace softbody
