// Projective Dynamics for the mass-spring model (Liu et al. 2013, "Fast simulation of
// mass-spring systems"; Bouaziz et al. 2014): backward Euler solved by local/global
// iterations with one constant matrix per body and step size (coordinate_matrix.h), factored
// once (sparse_cholesky.h: CHOLMOD's supernodal factor by default) and reused by every
// iteration of every step.
//
//   global matrix  A = M / h^2 + sum_e (k_e + kd_e / h) (e_a - e_b)(e_a - e_b)^T
//                              + sum_t (K_t + Kd_t / h) |g0_t|^2 S_t        (per coordinate)
//
// with S_t = I - 11^T / 4 on a tet's corners and g0_t its rest volume gradients. One iteration
// is x <- x - alpha A^-1 grad Phi(x) (incremental_potential.h). For springs this is exactly
// Liu's local step (project each spring to its rest length, d = l0 n) followed by the global
// solve A x = M y / h^2 + M g + J d; the volume term enters the same way with the target
// p = x - K (V - V0) / w g that reproduces its force, and the damping (taken implicitly along
// the step's initial axes, as in Implicit Euler) through its Laplacian in A. So the iterations
// converge to the same backward-Euler solution as Implicit Euler's Newton method, only
// linearly, and each is cheap: one element pass and one triangular solve pair for x, y and z
// together. A step
// length alpha < 1 is taken only when the full one would raise Phi (never for springs alone,
// where A bounds the Hessian). With ImplicitSettings::projectiveHistory > 0 the solve is the
// initial inverse Hessian of L-BFGS (Liu et al. 2017, "Quasi-Newton methods for real-time
// simulation of hyperelastic materials"): the same cost per iteration, far fewer iterations on
// stiff bodies, where plain PD stalls on the bending modes its isotropic matrix overestimates.
// The floor is the shared active set (implicit_solve.h): held
// points move along it by the filtered direction S A^-1 S grad Phi, still a descent direction.
//
// The continuum models (tet_elasticity.h) run the same way, as Liu et al. 2017 do for
// hyperelastic materials: Phi and its gradient are the model's own, and A gains per tet the
// Laplacian w_t (g_a . g_b) of its shape gradients with w_t = (2 mu + lambda) V0 (1 + beta / h),
// the stiffest linear modulus (with its viscosity) along the tet's strains. A only steers the
// iterations, so the answer is backward Euler's for the model; no local projection is needed.
#pragma once

#include "softbody/common/state.h"
#include "softbody/common/step_plan.h"
#include "softbody/massspring/implicit_integrator.h"
#include "softbody/massspring/implicit_solve.h"

#include "softbody/common/sparse_cholesky.h"
#include "softbody/massspring/coordinate_matrix.h"

#include <memory>

namespace softbody
{

class ProjectiveDynamicsStepper final : public ImplicitIntegrator
{
public:
  ProjectiveDynamicsStepper(const Topology& topology, const BodyElements& elements,
    const PointMasses& masses, const std::vector<Vec3>& restPositions,
    const SceneSettings& scene);

  /// One step of h; factors A first when h differs from the last step's (Stage::LinearSolve).
  void step(double h, DynamicState& state, StepPlan& plan) override;

  const ImplicitConvergence& convergence() const override { return Convergence; }
  IncrementalPotential& potential() override { return *Potential; }
  ContactPlanes& contactPlanes() override { return Solver.contactPlanes(); }
  /// Wall time of the last factorization [s], the factor's nonzeros and its bytes.
  double factorSeconds() const { return FactorSeconds; }
  std::size_t factorNonZeros() const { return FactorNonZeros; }
  std::size_t factorBytes() const { return FactorBytes; }
  int factorizations() const { return Factorizations; }

private:
  void factor(double h);
  /// direction = -S A^-1 S q for the filtered vector q.
  void solve(const std::vector<Vec3>& q, const MotionFilter& filter, std::vector<Vec3>& direction);
  /// The L-BFGS direction with A^-1 as initial inverse Hessian (plain PD with no history).
  void direction(const ImplicitStepSolver::Iterate& at, std::vector<Vec3>& direction);

  CoordinateMatrix Matrix;
  SparseCholesky Cholesky;
  std::unique_ptr<IncrementalPotential> Potential; ///< the body's material model
  ImplicitStepSolver Solver;
  double FactoredStep = 0.0;
  double FactorSeconds = 0.0;
  std::size_t FactorNonZeros = 0;
  std::size_t FactorBytes = 0;
  int Factorizations = 0;
  ImplicitConvergence Convergence;
  struct Pair
  {
    std::vector<Vec3> s, y; ///< x and filtered-gradient differences of one iteration
    double rho = 0.0;       ///< 1 / (y . s)
  };
  int History = 0;
  std::vector<Pair> Pairs;  ///< oldest first
  std::vector<Vec3> LastX, LastGradient, Q;
  Eigen::MatrixXd Rhs; ///< the three coordinates' right-hand sides, solved in place
  std::vector<double> Alpha;
};

} // namespace softbody
