#include "softbody/massspring/block_pcg.h"

#include "softbody/common/parallel.h"

#include <Eigen/LU>

#include <cmath>

namespace softbody
{
namespace
{

constexpr std::size_t kGrain = 2048;

double dot(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b)
{
  return parallelSum(a.size(), [&](std::size_t i) { return a[i].dot(b[i]); });
}

void invertDiagonal(const BlockSparseMatrix& A, const MotionFilter& filter,
  std::vector<Mat3>& inverse)
{
  inverse.resize(A.rowCount());
  parallelFor(A.rowCount(), kGrain, [&](std::size_t i) {
    const Mat3& d = A.block(A.diagonalSlot(i));
    bool invertible = false;
    double determinant = 0.0;
    const bool active = filter.moves(i);
    if (active)
    {
      d.computeInverseAndDetWithCheck(inverse[i], determinant, invertible);
    }
    if (!invertible)
    {
      // Only for rows outside the solve, or a singular block (then its scale still helps).
      const double trace = d.trace();
      inverse[i] = (active && trace > 0.0) ? Mat3(Mat3::Identity() * (3.0 / trace)) : Mat3::Zero();
    }
  });
}

} // namespace

PcgResult solveBlockPcg(const BlockSparseMatrix& A, const MotionFilter& filter,
  const std::vector<Eigen::Vector3d>& b, double relativeTolerance, int maxIterations,
  std::vector<Eigen::Vector3d>& x, PcgScratch& s, PcgPreconditioner* preconditioner)
{
  const std::size_t n = A.rowCount();
  if (!preconditioner)
  {
    invertDiagonal(A, filter, s.inverseDiagonal);
  }
  // z = S P^-1 r (block Jacobi fused into the loop that updates r).
  const auto precondition = [&] {
    if (preconditioner)
    {
      preconditioner->apply(s.residual, s.preconditioned);
      parallelFor(n, kGrain, [&](std::size_t i) { s.preconditioned[i] = filter.apply(i, s.preconditioned[i]); });
    }
  };
  const auto blockJacobi = [&](std::size_t i) {
    if (!preconditioner)
    {
      s.preconditioned[i] = filter.apply(i, s.inverseDiagonal[i] * s.residual[i]);
    }
  };
  x.assign(n, Eigen::Vector3d::Zero());
  s.residual.resize(n);
  s.preconditioned.resize(n);
  s.direction.resize(n);
  parallelFor(n, kGrain, [&](std::size_t i) {
    s.residual[i] = filter.apply(i, b[i]);
    blockJacobi(i);
  });
  precondition();
  parallelFor(n, kGrain, [&](std::size_t i) { s.direction[i] = s.preconditioned[i]; });

  PcgResult result;
  const double bNorm = std::sqrt(dot(s.residual, s.residual));
  if (!(bNorm > 0.0))
  {
    result.converged = true;
    return result;
  }
  const double goal = relativeTolerance * bNorm;
  double rz = dot(s.residual, s.preconditioned);
  double rNorm = bNorm;
  while (result.iterations < maxIterations && rNorm > goal)
  {
    A.multiply(s.direction, s.product);
    const double curvature = dot(s.direction, s.product);
    if (!(curvature > 0.0))
    {
      result.indefinite = true; // not positive definite along this direction (or breakdown)
      break;                    // keep what we have
    }
    const double alpha = rz / curvature;
    parallelFor(n, kGrain, [&](std::size_t i) {
      x[i] += alpha * s.direction[i];
      s.residual[i] -= alpha * filter.apply(i, s.product[i]);
      blockJacobi(i);
    });
    ++result.iterations;
    rNorm = std::sqrt(dot(s.residual, s.residual));
    if (rNorm <= goal)
    {
      break; // no preconditioner application for a direction that will not be taken
    }
    precondition();
    const double rzNext = dot(s.residual, s.preconditioned);
    const double beta = rzNext / rz;
    rz = rzNext;
    parallelFor(n, kGrain, [&](std::size_t i) {
      s.direction[i] = s.preconditioned[i] + beta * s.direction[i];
    });
  }
  result.relativeResidual = rNorm / bNorm;
  result.converged = rNorm <= goal;
  return result;
}

} // namespace softbody
