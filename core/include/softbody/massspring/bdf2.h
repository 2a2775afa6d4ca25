// The second-order backward differentiation formula (BDF2) for the mass-spring model, through
// Implicit Euler's solve. With the step ratio w = h / h_prev, variable-step BDF2 is
//
//   x+ - a x + b x- = beta h v+,   v+ - a v + b v- = beta h M^-1 f(x+, v+),
//   a = (1 + w)^2 / (1 + 2w),  b = w^2 / (1 + 2w),  beta = (1 + w) / (1 + 2w)
//
// (x-, x, x+ at t - h_prev, t, t + h; a = 4/3, b = 1/3, beta = 2/3 at a constant step). Both
// lines are backward Euler of the step beta h from the extrapolated state (x^, v^) =
// (a x - b x-, a v - b v-): x+ = x^ + beta h v+ and v+ = v^ + beta h M^-1 f. So one BDF2 step is
// one Implicit Euler step of beta h from (x^, v^) placed at t + h - beta h: the same incremental
// potential, Newton solve, contacts, damping (its force -D v+ is -D (x+ - x^) / (beta h), the
// form the potential has) and loads at the step's end time, for every material model.
//
// Second order, A-stable and L-stable like backward Euler: it damps the modes a step cannot
// resolve (amplification -> 0 as h w -> infinity), but a resolved mode of frequency w loses
// O((h w)^4) of its amplitude per step where backward Euler takes O((h w)^2). The first step,
// and a step more than kBdf2MaxStepRatio times the one before it, are backward Euler steps
// (bdf2_formula.h: isBdf2Step): the history they leave makes the next one BDF2.
#pragma once

#include "softbody/integrators/bdf2_formula.h"
#include "softbody/massspring/implicit_euler.h"

namespace softbody
{

/// Error control's factor from |halves - whole| to the halves' error for a BDF2 step of h after
/// one of previousStep (0: none): the whole step and the halves have different step ratios,
/// so different error constants (error_control.h: ErrorControl::halvesErrorFactor).
double bdf2HalvesErrorFactor(double h, double previousStep);

/// Restarts point i's history from its current state, as if it had moved at its current
/// velocity through the last step: for a point whose velocity a contact response (or any
/// correction after the solve) changed, the last two states no longer lie on one smooth
/// motion, and extrapolating them would carry the velocity it had before into the next step
/// (a point stopped on the floor would be sent back up by BDF2's -b v- term).
inline void restartBdf2History(std::size_t i, DynamicState& state)
{
  if (state.previousPositions.size() == state.positions.size() && state.previousStep > 0.0)
  {
    state.previousPositions[i] = state.positions[i] - state.previousStep * state.velocities[i];
    state.previousVelocities[i] = state.velocities[i];
  }
}

class Bdf2Stepper final : public ImplicitIntegrator
{
public:
  Bdf2Stepper(const Topology& topology, const BodyElements& elements, const PointMasses& masses,
    const std::vector<Vec3>& restPositions, const SceneSettings& scene);

  /// One BDF2 step of h from the state and its history (previousPositions, previousVelocities,
  /// previousStep), which it updates; a backward-Euler step where there is none. A point the
  /// solve's contact response changed the velocity of gets its history restarted
  /// (restartBdf2History); so must the caller's corrections after the step.
  void step(double h, DynamicState& state, StepPlan& plan) override;

  const ImplicitConvergence& convergence() const override { return BackwardEuler.convergence(); }
  IncrementalPotential& potential() override { return BackwardEuler.potential(); }
  ContactPlanes& contactPlanes() override { return BackwardEuler.contactPlanes(); }
  std::string solverWarning() const override { return BackwardEuler.solverWarning(); }
  const CoordinatePreconditioner* coordinatePreconditioner() const override
  {
    return BackwardEuler.coordinatePreconditioner();
  }

private:
  /// restartBdf2History for the points whose velocity is not the solve's (x+ - start) / step:
  /// those the contact response acted on. h is the whole step.
  void restartWhereTheResponseActed(double h, double solveStep, DynamicState& state);

  ImplicitEulerStepper BackwardEuler;
  DynamicState Extrapolated;
  std::vector<Vec3> ExtrapolatedStart; ///< x^ (the solve overwrites Extrapolated's positions)
};

} // namespace softbody
