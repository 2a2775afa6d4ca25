#include "softbody/massspring/coordinate_solver.h"

#include "softbody/massspring/amg_preconditioner.h"

#include <Eigen/IterativeLinearSolvers>

#include <stdexcept>

namespace softbody
{
namespace
{

/// The complete factor: P^-1 = A^-1.
class CompleteCholesky final : public CoordinateSolver
{
public:
  explicit CompleteCholesky(CholeskyBackend backend) : Cholesky(backend) {}
  std::string factor(const Eigen::SparseMatrix<double>& a) override { return Cholesky.factor(a); }
  bool factored() const override { return Cholesky.factored(); }
  void solve(Eigen::MatrixXd& columns) override { Cholesky.solve(columns); }
  std::size_t bytes() const override { return Cholesky.factorBytes(); }

private:
  SparseCholesky Cholesky;
};

/// Eigen's incomplete Cholesky with no fill.
class IncompleteCholesky final : public CoordinateSolver
{
public:
  std::string factor(const Eigen::SparseMatrix<double>& a) override
  {
    // Eigen shifts the scaled diagonal until the incomplete factor exists, so it fails only on
    // a matrix it cannot scale (a zero or negative diagonal).
    Factor.compute(a);
    Factored = Factor.info() == Eigen::Success;
    return Factored ? std::string() : "the incomplete Cholesky factorization reported a numerical issue";
  }
  bool factored() const override { return Factored; }
  void solve(Eigen::MatrixXd& columns) override
  {
    // Eigen's incomplete factor solves one right-hand side at a time; each goes through a kept
    // column so that no CG iteration allocates.
    for (Eigen::Index c = 0; c < columns.cols(); ++c)
    {
      Column = Factor.solve(columns.col(c));
      columns.col(c) = Column;
    }
  }
  std::size_t bytes() const override
  {
    if (!Factored)
    {
      return 0;
    }
    // L's values and row indices, its column starts, the scaling and the two permutations.
    const auto& l = Factor.matrixL();
    const std::size_t n = static_cast<std::size_t>(l.cols());
    return static_cast<std::size_t>(l.nonZeros()) * (sizeof(double) + sizeof(int)) +
      (n + 1) * sizeof(int) + n * (sizeof(double) + 2 * sizeof(int));
  }

private:
  Eigen::IncompleteCholesky<double, Eigen::Lower, Eigen::AMDOrdering<int>> Factor;
  bool Factored = false;
  Eigen::VectorXd Column;
};

} // namespace

std::unique_ptr<CoordinateSolver> makeCoordinateSolver(LinearPreconditioner kind, CholeskyBackend backend)
{
  switch (kind)
  {
    case LinearPreconditioner::Coordinate:
      return std::make_unique<CompleteCholesky>(backend);
    case LinearPreconditioner::IncompleteCoordinate:
      return std::make_unique<IncompleteCholesky>();
    case LinearPreconditioner::AlgebraicMultigrid:
      return makeAlgebraicMultigrid();
    case LinearPreconditioner::BlockJacobi:
      break;
  }
  throw std::logic_error("block Jacobi has no coordinate solver");
}

} // namespace softbody
