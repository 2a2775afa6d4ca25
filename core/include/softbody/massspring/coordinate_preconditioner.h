// A preconditioner for the conjugate gradients of Newton's step systems that sees the whole
// mesh: a sparse Cholesky factor of the isotropic step matrix A(h) (coordinate_matrix.h),
// applied to x, y and z with one solve: P^-1 r = (A^-1 r_x, A^-1 r_y, A^-1 r_z). (A constant
// factor between A and the Hessian does not change conjugate gradients' iterates.)
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
// The factor is complete (SparseCholesky: CHOLMOD or Eigen) or incomplete (Eigen's incomplete
// Cholesky with no fill, after its own diagonal scaling and with the diagonal shift it adds
// until the factor exists). The complete factor's fill grows faster than the mesh (about
// n^(4/3) nonzeros for a 3D mesh of n points under nested dissection); the incomplete one
// keeps A's pattern, at the price of more CG iterations.
#pragma once

#include "softbody/common/sparse_cholesky.h"
#include "softbody/massspring/block_pcg.h"
#include "softbody/massspring/coordinate_matrix.h"

#include <memory>
#include <string>
#include <vector>

namespace softbody
{

class CoordinatePreconditioner final : public PcgPreconditioner
{
public:
  CoordinatePreconditioner(const Topology& topology, const BodyElements& elements,
    const PointMasses& masses, const std::vector<Vec3>& restPositions, CholeskyBackend backend,
    bool incomplete = false);
  ~CoordinatePreconditioner() override;

  /// Makes the factor ready for a system of step h (with `inertia`: M / h^2 in it; the static
  /// solve has none and h = infinity) with the points `active` is 0 at held by conditions
  /// (IncrementalPotential::active()). Refactors only when needed (see above). Returns an empty string when ready, else why the factorization
  /// failed (then apply() must not be called).
  std::string prepare(double h, bool inertia, const std::vector<char>& active);

  /// z = P^-1 r over all points (held and fixed points get z = r's, which the filter zeroes).
  void apply(const std::vector<Vec3>& r, std::vector<Vec3>& z) override;

  int factorizations() const { return Factorizations; }
  double factorSeconds() const { return FactorSeconds; } ///< all factorizations together
  std::size_t factorBytes() const;
  bool incomplete() const { return static_cast<bool>(Incomplete); }

  /// The largest ratio between the step and the factored one at which the factor is reused.
  static constexpr double kStepRatio = 1.4142135623730951;

private:
  CoordinateMatrix Matrix;
  SparseCholesky Cholesky;
  struct IncompleteFactor;
  std::unique_ptr<IncompleteFactor> Incomplete; ///< null: the complete factor
  double FactoredStep = 0.0;
  bool FactoredInertia = true;
  std::vector<char> FactoredHeld; ///< per row of A: held by a condition when factored
  std::vector<char> Held;
  Eigen::MatrixXd Columns; ///< x, y and z of the right-hand side, solved in place
  int Factorizations = 0;
  double FactorSeconds = 0.0;
};

} // namespace softbody
