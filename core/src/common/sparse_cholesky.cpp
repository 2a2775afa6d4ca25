#include "softbody/common/sparse_cholesky.h"

#include "softbody/common/parallel.h"

#include <Eigen/SparseCholesky>

#include <suitesparse/cholmod.h>

#include <algorithm>
#include <new>
#include <string>

namespace softbody
{

const char* choleskyBackendName(CholeskyBackend backend)
{
  return backend == CholeskyBackend::CholmodSupernodal ? "CHOLMOD supernodal" : "Eigen simplicial";
}

struct SparseCholesky::Impl
{
  Impl()
  {
    cholmod_start(&Common);
    Common.supernodal = CHOLMOD_SUPERNODAL;
    Common.print = 0; // failures are reported through factor()'s message, not CHOLMOD's printf
  }
  ~Impl()
  {
    freeAll();
    cholmod_finish(&Common);
  }
  void freeAll()
  {
    cholmod_free_factor(&Factor, &Common);
    cholmod_free_dense(&Solution, &Common);
    cholmod_free_dense(&WorkY, &Common);
    cholmod_free_dense(&WorkE, &Common);
  }

  cholmod_common Common{};
  cholmod_factor* Factor = nullptr;
  // cholmod_solve2's outputs and workspace, kept across solves (no allocation per solve).
  cholmod_dense* Solution = nullptr;
  cholmod_dense* WorkY = nullptr;
  cholmod_dense* WorkE = nullptr;

  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>> Simplicial;
  bool SimplicialAnalysed = false;
  bool SimplicialFactored = false;
  bool Empty = false; ///< a 0 x 0 matrix (every point fixed): nothing to factor or solve
};

namespace
{

/// CHOLMOD's view of an Eigen matrix's lower triangle (no copy; the matrix must be compressed).
cholmod_sparse viewLowerTriangle(const Eigen::SparseMatrix<double>& matrix)
{
  cholmod_sparse view{};
  view.nrow = static_cast<std::size_t>(matrix.rows());
  view.ncol = static_cast<std::size_t>(matrix.cols());
  view.nzmax = static_cast<std::size_t>(matrix.nonZeros());
  view.p = const_cast<int*>(matrix.outerIndexPtr());
  view.i = const_cast<int*>(matrix.innerIndexPtr());
  view.x = const_cast<double*>(matrix.valuePtr());
  view.stype = -1;
  view.itype = CHOLMOD_INT;
  view.xtype = CHOLMOD_REAL;
  view.dtype = CHOLMOD_DOUBLE;
  view.sorted = 1;
  view.packed = 1;
  return view;
}

std::string cholmodFailure(const cholmod_common& common, const cholmod_factor* factor)
{
  switch (common.status)
  {
    case CHOLMOD_NOT_POSDEF:
      return "the matrix is not positive definite (CHOLMOD stopped at column " +
        std::to_string(factor ? factor->minor : 0) + ")";
    case CHOLMOD_OUT_OF_MEMORY:
      return "CHOLMOD ran out of memory";
    case CHOLMOD_TOO_LARGE:
      return "the factor is too large for CHOLMOD's 32-bit indices";
    default:
      return "CHOLMOD failed with status " + std::to_string(common.status);
  }
}

} // namespace

SparseCholesky::SparseCholesky(CholeskyBackend backend)
  : Backend(backend)
  , Self(std::make_unique<Impl>())
{
}

SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

std::string SparseCholesky::factor(const Eigen::SparseMatrix<double>& input)
{
  try
  {
    Self->Empty = input.rows() == 0;
    if (Self->Empty)
    {
      return {}; // CHOLMOD refuses a 0 x 0 matrix as invalid input
    }
    Eigen::SparseMatrix<double> matrix = input;
    matrix.makeCompressed();
    if (Backend == CholeskyBackend::EigenSimplicial)
    {
      if (!Self->SimplicialAnalysed)
      {
        Self->Simplicial.analyzePattern(matrix);
        Self->SimplicialAnalysed = true;
      }
      Self->Simplicial.factorize(matrix);
      Self->SimplicialFactored = Self->Simplicial.info() == Eigen::Success;
      if (!Self->SimplicialFactored)
      {
        Self->SimplicialAnalysed = false;
        return "the matrix is not positive definite (Eigen's simplicial LL^T failed)";
      }
      return {};
    }
    cholmod_sparse view = viewLowerTriangle(matrix);
    cholmod_common& common = Self->Common;
    if (!Self->Factor)
    {
      Self->Factor = cholmod_analyze(&view, &common);
      if (!Self->Factor)
      {
        const std::string why = cholmodFailure(common, nullptr);
        Self->freeAll();
        return why;
      }
    }
    cholmod_factorize(&view, Self->Factor, &common);
    if (common.status != CHOLMOD_OK)
    {
      const std::string why = cholmodFailure(common, Self->Factor);
      Self->freeAll();
      return why;
    }
    return {};
  }
  catch (const std::bad_alloc&)
  {
    Self->freeAll();
    Self->SimplicialAnalysed = Self->SimplicialFactored = false;
    return "out of memory while factoring";
  }
}

bool SparseCholesky::factored() const
{
  if (Self->Empty)
  {
    return true;
  }
  return Backend == CholeskyBackend::EigenSimplicial ? Self->SimplicialFactored : Self->Factor != nullptr;
}

void SparseCholesky::solve(Eigen::MatrixXd& rhs) const
{
  if (Self->Empty)
  {
    return;
  }
  if (Backend == CholeskyBackend::EigenSimplicial)
  {
    // Eigen's triangular solves take one column at a time: one task per column.
    parallelFor(static_cast<std::size_t>(rhs.cols()), 1, [&](std::size_t column) {
      const auto c = static_cast<Eigen::Index>(column);
      rhs.col(c) = Self->Simplicial.solve(rhs.col(c));
    });
    return;
  }
  cholmod_dense b{};
  b.nrow = static_cast<std::size_t>(rhs.rows());
  b.ncol = static_cast<std::size_t>(rhs.cols());
  b.nzmax = b.nrow * b.ncol;
  b.d = b.nrow;
  b.x = rhs.data();
  b.xtype = CHOLMOD_REAL;
  b.dtype = CHOLMOD_DOUBLE;
  cholmod_solve2(CHOLMOD_A, Self->Factor, &b, nullptr, &Self->Solution, nullptr, &Self->WorkY,
    &Self->WorkE, &Self->Common);
  if (!Self->Solution)
  {
    throw std::bad_alloc(); // cholmod_solve2 fails only when it cannot allocate its output
  }
  const auto* x = static_cast<const double*>(Self->Solution->x);
  std::copy(x, x + b.nzmax, rhs.data());
}

std::size_t SparseCholesky::factorNonZeros() const
{
  if (Self->Empty)
  {
    return 0;
  }
  if (Backend == CholeskyBackend::EigenSimplicial)
  {
    return Self->SimplicialFactored
      ? static_cast<std::size_t>(Self->Simplicial.matrixL().nestedExpression().nonZeros())
      : 0;
  }
  return Self->Factor ? Self->Factor->xsize : 0;
}

std::size_t SparseCholesky::factorBytes() const
{
  if (Self->Empty)
  {
    return 0;
  }
  if (Backend == CholeskyBackend::EigenSimplicial)
  {
    return factorNonZeros() * (sizeof(double) + sizeof(int)); // a row index per value
  }
  // Supernodal: dense columns of values, one row-index list per supernode.
  return Self->Factor ? Self->Factor->xsize * sizeof(double) + Self->Factor->ssize * sizeof(int) : 0;
}

} // namespace softbody
