// The time integrators every method can be asked for, and one table of what is true of each:
// its name, order, whether it solves a system per step, whether the GPU stepper runs it, and
// its stability function. Code that needs such a fact reads it here instead of switching over
// the list, so a new integrator is one enumerator and one table row (plus its step).
#pragma once

#include "softbody/integrators/local_error.h"

#include <span>

namespace softbody
{

enum class Integrator
{
  Euler,       ///< x += h v(t);        v += h a(t)                 first order, needs damping
  Midpoint,    ///< RK2 through the midpoint state                  second order
  Verlet,      ///< Stoermer-Verlet in leapfrog form                second order, symplectic
  EulerCromer, ///< v += h a(t);        x += h v(t+h)               first order, symplectic
  // Implicit (implicit_euler.h, projective_dynamics.h): stable at any step, solved per step.
  ImplicitEuler,     ///< backward Euler by Newton's method with PCG   first order, dissipative
  ProjectiveDynamics, ///< backward Euler by local/global iterations (Liu et al. 2013)
  /// The static equilibrium at each step's end time, without inertia (static_solve.h): Newton
  /// on the elastic energy and the loads. Velocities are zero.
  Static,
  /// Second-order backward differentiation (bdf2.h): each step is a backward-Euler solve of
  /// 2h/3 from the state extrapolated from the last two, through the same Newton solve.
  /// Second order, L-stable, far less dissipative than Implicit Euler. (Last: the values
  /// before it are the filter's and the state files'.)
  Bdf2,
  /// Backward Euler by Vertex Block Descent (vertex_block_descent.h, Chen et al. 2024): colored
  /// Gauss-Seidel sweeps of per-point 3 x 3 Newton steps. First order, dissipative like
  /// Implicit Euler.
  VertexBlockDescent
};

struct IntegratorFacts
{
  Integrator integrator;
  const char* name; ///< as the filter's field data and every message say it
  int order;        ///< of accuracy in the step size
  /// Solves a system per step: no stability limit, and the automatic step is one per frame.
  bool implicit;
  bool symplectic;
  /// Acceleration evaluations per step (the cost model of the long-run warning).
  int forceEvaluationsPerStep;
  /// The velocity is the position difference of the last step (Verlet's staggered velocity),
  /// so a pass that moves a point (strain limit) must move its velocity too.
  bool velocityFromPositions;
  bool runsOnGpu; ///< the GPU stepper has its update kernels; others fall back to the CPU
  /// The integrator whose undamped stable step shows whether damping or stiffness limits this
  /// one's step (explicit Euler has none undamped, so it is measured against Euler-Cromer).
  Integrator undampedReference;
  /// What the plan says of the element pass and of the linear solve (implicit ones only).
  const char* forcesDetail;
  const char* linearSolve;
  /// Spectral radius of one step of size h on the damped oscillator x'' = -omega^2 x - c x'
  /// (the test equation the stable step is found on, stability.h).
  double (*amplificationRadius)(double h, double omega, double c);
  /// The embedded estimate of a step's local position error (local_error.h); null where there
  /// is none, and error control judges each step by step doubling.
  const EmbeddedErrorEstimate* localError;
};

/// Every integrator, in the order of the enumeration.
std::span<const IntegratorFacts> integratorTable();
const IntegratorFacts& factsOf(Integrator integrator);

inline const char* integratorName(Integrator integrator) { return factsOf(integrator).name; }
/// True for the integrators that solve a system per step (and have no stability limit).
inline bool isImplicit(Integrator integrator) { return factsOf(integrator).implicit; }

} // namespace softbody
