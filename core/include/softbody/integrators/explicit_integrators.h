// Explicit time integrators of the mass-spring thesis: Euler, Midpoint (RK2), Verlet and
// Euler-Cromer (symplectic Euler). Each advances positions and velocities by one step h using
// an acceleration evaluator a(x, v). Pinned points have a = 0 and v = 0 and never move.
#pragma once

#include "softbody/common/geometry.h"
#include "softbody/common/state.h"
#include "softbody/integrators/integrator.h"

#include <vector>

namespace softbody
{

/// Computes accelerations [m/s^2] for given positions and velocities at a time [s] (loads may
/// change with time; Midpoint evaluates at the step's middle).
class AccelerationEvaluator
{
public:
  virtual ~AccelerationEvaluator() = default;
  virtual void evaluate(double time, const std::vector<Vec3>& positions,
    const std::vector<Vec3>& velocities, std::vector<Vec3>& accelerations) const = 0;
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
