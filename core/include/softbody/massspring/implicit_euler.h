// Backward (implicit) Euler for the mass-spring model: each step minimizes the incremental
// potential (incremental_potential.h) by Newton's method (implicit_solve.h: line search, floor
// active set). Each Newton iteration solves H d = -grad Phi with block-Jacobi preconditioned
// conjugate gradients (block_pcg.h; or with the coordinate preconditioner,
// coordinate_preconditioner.h, when ImplicitSettings asks for it) on the assembled
// PSD-projected Hessian, or near the solution on the exact one where the model has it (the
// continuum models), to a relative accuracy that tightens as Newton converges
// (eta = min(0.1, r / r_0): quadratic convergence where the Hessian is exact) but never much
// below what the tolerance needs. Stable at any
// step, first order; its numerical dissipation grows with h (it damps the modes above ~1/h).
#pragma once

#include "softbody/massspring/block_pcg.h"
#include "softbody/massspring/coordinate_preconditioner.h"
#include "softbody/massspring/implicit_integrator.h"
#include "softbody/massspring/implicit_solve.h"
#include "softbody/massspring/model_potential_factory.h"

namespace softbody
{

class ImplicitEulerStepper final : public ImplicitIntegrator
{
public:
  /// With `equilibrium`, the potential drops inertia (IncrementalPotential::makeStatic): each
  /// step then solves for the static equilibrium (the Static integrator, static_solve.h).
  ImplicitEulerStepper(const Topology& topology, const BodyElements& elements,
    const PointMasses& masses, const std::vector<Vec3>& restPositions,
    const SceneSettings& scene, bool equilibrium = false);

  /// One backward-Euler step of h (positions and velocities; time and counters are the
  /// caller's). Times Stage::Forces (evaluations and assembly) and Stage::LinearSolve.
  void step(double h, DynamicState& state, StepPlan& plan) override;

  const ImplicitConvergence& convergence() const override { return Convergence; }
  IncrementalPotential& potential() override { return *Potential; }
  ContactPlanes& contactPlanes() override { return Solver.contactPlanes(); }
  std::string solverWarning() const override { return PreconditionerWarning; }
  /// The coordinate preconditioner, when the settings ask for one (null: block Jacobi).
  const CoordinatePreconditioner* coordinatePreconditioner() const override { return Coordinate.get(); }
  /// CG iteration limit per Newton iteration.
  static constexpr int kMaxLinearIterations = 2000;
  /// Newton iterations that took the exact Hessian's direction, and those that tried it and fell
  /// back to the projected one (indefinite, or no descent), since construction.
  long exactHessianSteps() const { return ExactHessianSteps; }
  long exactHessianFallbacks() const { return ExactHessianFallbacks; }

private:
  /// The coordinate preconditioner made ready for this system, or null for block Jacobi.
  PcgPreconditioner* preconditioner(double h);

  std::unique_ptr<IncrementalPotential> Potential; ///< the body's material model
  ImplicitStepSolver Solver;
  BlockSparseMatrix Hessian;
  PcgScratch LinearWork;
  std::unique_ptr<CoordinatePreconditioner> Coordinate;
  bool Equilibrium = false;
  std::string PreconditionerWarning; ///< set when the factor failed: block Jacobi from then on
  std::vector<Vec3> Rhs;
  ImplicitConvergence Convergence;
  long ExactHessianSteps = 0;
  long ExactHessianFallbacks = 0;
};

} // namespace softbody
