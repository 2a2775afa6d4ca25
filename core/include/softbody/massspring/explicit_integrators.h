// Explicit time integrators of the mass-spring thesis: Euler, Midpoint (RK2), Verlet and
// Euler-Cromer (symplectic Euler). Each advances positions and velocities by one step h using
// an acceleration evaluator a(x, v). Pinned points have a = 0 and v = 0 and never move.
#pragma once

#include "softbody/common/geometry.h"
#include "softbody/common/state.h"

#include <vector>

namespace softbody
{

enum class Integrator
{
  Euler,       ///< x += h v(t);        v += h a(t)                 first order, needs damping
  Midpoint,    ///< RK2 through the midpoint state                  second order
  Verlet,      ///< Stoermer-Verlet in leapfrog form (see below)    second order, symplectic
  EulerCromer, ///< v += h a(t);        x += h v(t+h)               first order, symplectic
  // Implicit (implicit_euler.h, projective_dynamics.h): stable at any step, solved per step.
  ImplicitEuler,     ///< backward Euler by Newton's method with PCG   first order, dissipative
  ProjectiveDynamics ///< backward Euler by local/global iterations (Liu et al. 2013)
};

const char* integratorName(Integrator integrator);

/// True for the integrators that solve a system per step (and have no stability limit).
inline bool isImplicit(Integrator integrator)
{
  return integrator == Integrator::ImplicitEuler || integrator == Integrator::ProjectiveDynamics;
}

/// Computes accelerations [m/s^2] for given positions and velocities.
class AccelerationEvaluator
{
public:
  virtual ~AccelerationEvaluator() = default;
  virtual void evaluate(const std::vector<Vec3>& positions, const std::vector<Vec3>& velocities,
    std::vector<Vec3>& accelerations) const = 0;
};

/// Work arrays reused across steps (no allocation in the step loop).
struct IntegratorScratch
{
  std::vector<Vec3> acceleration;
  std::vector<Vec3> midPositions;
  std::vector<Vec3> midVelocities;
};

/// Advances `state` by h (positions, velocities, time, stepCount, previousStep) with an
/// explicit integrator (the implicit ones have their own steppers).
void integrateStep(Integrator integrator, double h, const AccelerationEvaluator& evaluator,
  DynamicState& state, IntegratorScratch& scratch);

} // namespace softbody
