// A preconditioner for the conjugate gradients of Newton's step systems that sees the whole
// mesh: an approximate inverse of the isotropic step matrix A(h) (coordinate_matrix.h), made
// once and applied to x, y and z: P^-1 r = (A^-1 r_x, A^-1 r_y, A^-1 r_z), A^-1 exact or
// approximate by the kind (below). (A constant factor between A and the Hessian does not change
// conjugate gradients' iterates.)
//
// Block Jacobi needs many iterations on large meshes because it does not see the long-range
// coupling: its iteration count grows with the mesh's diameter in elements. A(h) has the
// Hessian's sparsity and its stiffest isotropic moduli at rest, so the preconditioned system's
// condition number is bounded by how far the deformation and anisotropy take H from A, not by
// the mesh size. The factor is reused across Newton iterations and steps: it is refactored only
// when the step leaves [h_f / sqrt(2), sqrt(2) h_f] of the factored step h_f, or the set of
// points the conditions hold changes (a held point's row is decoupled to the identity). Points
// held by contacts (sliding on a plane, or stuck by static friction) keep their rows: the
// filter removes their motion after the solve, and a contact set that changes from one Newton
// iteration to the next would otherwise refactor at every one.
//
// What is made from A is a CoordinateSolver (coordinate_solver.h): a complete factor
// (SparseCholesky: CHOLMOD or Eigen), an incomplete one (Eigen's incomplete Cholesky with no
// fill, after its own diagonal scaling and with the diagonal shift it adds until the factor
// exists), or an algebraic multigrid hierarchy (amg_preconditioner.h: one V-cycle per
// coordinate). The complete factor's fill grows faster than the mesh (about n^(4/3) nonzeros
// for a 3D mesh of n points under nested dissection); the incomplete one keeps A's pattern, at
// the price of more CG iterations; the hierarchy is a small multiple of A and its V-cycle's
// work is linear in n.
#pragma once

#include "softbody/massspring/block_pcg.h"
#include "softbody/massspring/coordinate_matrix.h"
#include "softbody/massspring/coordinate_solver.h"

#include <memory>
#include <string>
#include <vector>

namespace softbody
{

class CoordinatePreconditioner final : public PcgPreconditioner
{
public:
  CoordinatePreconditioner(const Topology& topology, const BodyElements& elements,
    const PointMasses& masses, const std::vector<Vec3>& restPositions, LinearPreconditioner kind,
    CholeskyBackend backend);
  ~CoordinatePreconditioner() override;

  /// Makes the factor ready for a system of step h (with `inertia`: M / h^2 in it; the static
  /// solve has none and h = infinity) with the points `active` is 0 at held by conditions
  /// (IncrementalPotential::active()). Refactors only when needed (see above). Returns an empty
  /// string when ready, else why the factorization failed (then apply() must not be called).
  std::string prepare(double h, bool inertia, const std::vector<char>& active);

  /// z = P^-1 r over all points (held and fixed points get z = r's, which the filter zeroes).
  void apply(const std::vector<Vec3>& r, std::vector<Vec3>& z) override;

  int factorizations() const { return Factorizations; }
  double factorSeconds() const { return FactorSeconds; } ///< all factorizations together
  std::size_t factorBytes() const { return Solver->bytes(); }
  LinearPreconditioner kind() const { return Kind; }

  /// The largest ratio between the step and the factored one at which the factor is reused.
  static constexpr double kStepRatio = 1.4142135623730951;

private:
  CoordinateMatrix Matrix;
  LinearPreconditioner Kind;
  std::unique_ptr<CoordinateSolver> Solver;
  double FactoredStep = 0.0;
  bool FactoredInertia = true;
  std::vector<char> FactoredHeld; ///< per row of A: held by a condition when factored
  std::vector<char> Held;
  Eigen::MatrixXd Columns; ///< x, y and z of the right-hand side, solved in place
  int Factorizations = 0;
  double FactorSeconds = 0.0;
};

} // namespace softbody
