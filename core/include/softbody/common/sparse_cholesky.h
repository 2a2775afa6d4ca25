// A sparse Cholesky factorization of a symmetric positive definite matrix, for the solves that
// share one matrix across many right-hand sides (Projective Dynamics' global step, the
// coordinate preconditioner of Newton's conjugate gradients).
//
// Two backends, so that the benchmarks can measure one against the other in the same run:
// CHOLMOD's supernodal factorization (SuiteSparse; its dense blocks go through BLAS, and its
// solve takes all right-hand sides in one pass over the factor) with CHOLMOD's choice of
// fill-reducing ordering (AMD, or METIS nested dissection where AMD fills in much), and
// Eigen's simplicial LL^T with AMD (one column at a time, the columns in parallel). The pattern is analysed once; later
// factorizations with the same pattern reuse the ordering and the symbolic factor.
//
// The factorization and CHOLMOD's solve are serial (CHOLMOD links Debian's serial OpenBLAS),
// and Eigen's columns are independent, so the factor, and everything computed from it, is the
// same for any thread count.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <memory>
#include <string>

namespace softbody
{

enum class CholeskyBackend
{
  CholmodSupernodal,
  EigenSimplicial
};

const char* choleskyBackendName(CholeskyBackend backend);

class SparseCholesky
{
public:
  explicit SparseCholesky(CholeskyBackend backend = CholeskyBackend::CholmodSupernodal);
  ~SparseCholesky();
  SparseCholesky(SparseCholesky&&) noexcept;
  SparseCholesky& operator=(SparseCholesky&&) noexcept;

  /// Factors `matrix` (both triangles stored; the lower one is read; 0 x 0 is factored as
  /// nothing: every point fixed). The first call, and any
  /// call after a failure, analyses the pattern. Returns an empty string on success, else why
  /// it failed (not positive definite at a column, out of memory), and then holds no factor.
  std::string factor(const Eigen::SparseMatrix<double>& matrix);
  bool factored() const;

  /// Solves A X = B for every column of `rhs` in place.
  void solve(Eigen::MatrixXd& rhs) const;

  /// Nonzeros of the factor L (supernodal: including the explicit zeros of its dense blocks).
  std::size_t factorNonZeros() const;
  /// Bytes the factor's values and indices take.
  std::size_t factorBytes() const;
  CholeskyBackend backend() const { return Backend; }

private:
  struct Impl;
  CholeskyBackend Backend;
  std::unique_ptr<Impl> Self;
};

} // namespace softbody
