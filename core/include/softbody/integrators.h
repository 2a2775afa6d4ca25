// Explicit time integrators of the mass-spring thesis: Euler, Midpoint (RK2), Verlet and
// Euler-Cromer (symplectic Euler). Each advances positions and velocities by one step h using
// an acceleration evaluator a(x, v). Pinned points have a = 0 and v = 0 and never move.
#pragma once

#include "softbody/geometry.h"

#include <vector>

namespace softbody
{

enum class Integrator
{
  Euler,       ///< x += h v(t);        v += h a(t)                 first order, needs damping
  Midpoint,    ///< RK2 through the midpoint state                  second order
  Verlet,      ///< Stoermer-Verlet in leapfrog form (see below)    second order, symplectic
  EulerCromer  ///< v += h a(t);        x += h v(t+h)               first order, symplectic
};

const char* integratorName(Integrator integrator);

/// Computes accelerations [m/s^2] for given positions and velocities.
class AccelerationEvaluator
{
public:
  virtual ~AccelerationEvaluator() = default;
  virtual void evaluate(const std::vector<Vec3>& positions, const std::vector<Vec3>& velocities,
    std::vector<Vec3>& accelerations) const = 0;
};

/// The dynamic state; a copy of it is a complete snapshot (the frame cache stores these).
struct DynamicState
{
  std::vector<Vec3> positions;  ///< [m]
  /// [m/s]. For Verlet this is the staggered velocity v(t - h/2) of position Verlet, i.e.
  /// (x(t) - x(t-h)) / h: Stoermer-Verlet x+ = 2x - x- + h^2 a is exactly the leapfrog
  /// v(t+h/2) = v(t-h/2) + h a(t), x(t+h) = x(t) + h v(t+h/2), which needs no x- array and
  /// lets the step size change between frames.
  std::vector<Vec3> velocities;
  double time = 0.0;            ///< simulated time [s]
  unsigned long long stepCount = 0;
  /// Size of the previous step [s] (0 before the first). Verlet's kick spans the half steps on
  /// both sides, (h_prev + h) / 2, so its first step is the half kick that starts leapfrog
  /// exactly: free fall is reproduced to rounding.
  double previousStep = 0.0;
  /// History of models whose links change as they move (PBD plastic and breakable links):
  /// the current rest length and broken flag of each link. Empty for models without any.
  std::vector<double> linkRestLengths;
  std::vector<unsigned char> linkBroken;
};

/// Work arrays reused across steps (no allocation in the step loop).
struct IntegratorScratch
{
  std::vector<Vec3> acceleration;
  std::vector<Vec3> midPositions;
  std::vector<Vec3> midVelocities;
};

/// Advances `state` by h (positions, velocities, time, stepCount, previousStep).
void integrateStep(Integrator integrator, double h, const AccelerationEvaluator& evaluator,
  DynamicState& state, IntegratorScratch& scratch);

} // namespace softbody
