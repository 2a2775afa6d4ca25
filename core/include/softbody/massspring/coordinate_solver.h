// What the coordinate preconditioner (coordinate_preconditioner.h) makes from its matrix A and
// applies at every CG iteration: an approximate inverse of A, applied to the three coordinates'
// columns. The preconditioner owns the matrix and the rule of when to remake it; a solver
// owns only the approximation.
//
// Three of them, one per LinearPreconditioner value that uses A: the complete sparse Cholesky
// factor (Coordinate), Eigen's incomplete one (IncompleteCoordinate), both here, and a
// BoomerAMG hierarchy (AlgebraicMultigrid, amg_preconditioner.h).
#pragma once

#include "softbody/common/sparse_cholesky.h"
#include "softbody/massspring/mass_spring_settings.h"

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <cstddef>
#include <memory>
#include <string>

namespace softbody
{

class CoordinateSolver
{
public:
  virtual ~CoordinateSolver() = default;

  /// Makes the approximate inverse of `a` (symmetric positive definite, both triangles
  /// stored). Returns an empty string when ready, else why it could not be made (and then
  /// factored() is false).
  virtual std::string factor(const Eigen::SparseMatrix<double>& a) = 0;
  virtual bool factored() const = 0;
  /// columns <- P^-1 columns, each column one coordinate. P^-1 is symmetric positive definite
  /// and the same at every call until the next factor(), as conjugate gradients need.
  virtual void solve(Eigen::MatrixXd& columns) = 0;
  /// Bytes the approximation holds (the factor, or the hierarchy's operators).
  virtual std::size_t bytes() const = 0;
};

/// The solver of a preconditioner that uses A (not BlockJacobi). Throws InvalidInputError for
/// AlgebraicMultigrid in a build without hypre.
std::unique_ptr<CoordinateSolver> makeCoordinateSolver(LinearPreconditioner kind, CholeskyBackend backend);

} // namespace softbody
