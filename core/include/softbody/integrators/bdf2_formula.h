// Variable-step BDF2's formula, apart from its solve (massspring/bdf2.h): the coefficients of a
// step of ratio w = h / h_prev to the one before it, its local error constant, and which steps
// have the history to be BDF2 steps (the others are backward Euler's).
#pragma once

#include "softbody/common/state.h"

namespace softbody
{

/// BDF2's coefficients for a step of ratio w = h / h_prev to the previous one:
/// x+ - a x + b x- = beta h v+ (and the same for v).
struct Bdf2Coefficients
{
  double a, b, beta;
  static Bdf2Coefficients forRatio(double w)
  {
    const double d = 1.0 + 2.0 * w;
    return { (1.0 + w) * (1.0 + w) / d, w * w / d, (1.0 + w) / d };
  }
  /// The local error of a step of ratio w is C(w) h^3 y''' with C(w) = -(1 + w)^2 /
  /// (6 w (1 + 2w)) (-2/9 at a constant step): |C(w)|.
  static double errorConstant(double w) { return (1.0 + w) * (1.0 + w) / (6.0 * w * (1.0 + 2.0 * w)); }
};

/// The largest step ratio h / h_prev a BDF2 step is taken at. Variable-step BDF2 is
/// zero-stable for sequences of ratios below 1 + sqrt(2); a single larger one is not
/// unstable, and the error controller's whole step, which follows two half steps and may be
/// twice their sum, has a ratio of up to 4 (the steps it keeps, up to 2). Beyond that the
/// extrapolation amplifies the history (a = 2.8 at 4, 51 at 100): backward Euler instead.
inline constexpr double kBdf2MaxStepRatio = 4.0;

/// Whether a step of h from `state` is a BDF2 step: the state holds the positions and
/// velocities before its last step, and h is at most kBdf2MaxStepRatio times that step.
inline bool isBdf2Step(const DynamicState& state, double h)
{
  const std::size_t n = state.positions.size();
  return state.previousPositions.size() == n && state.previousVelocities.size() == n &&
    state.previousStep > 0.0 && h / state.previousStep <= kBdf2MaxStepRatio;
}

/// The constant of BDF2's embedded estimate for a step of h after one of previousStep:
/// |C(h / previousStep)|, or 0 where the step is backward Euler's (ErrorControl::errorConstant).
inline double bdf2EstimateConstant(double h, double previousStep)
{
  const bool bdf2 = previousStep > 0.0 && h / previousStep <= kBdf2MaxStepRatio;
  return bdf2 ? Bdf2Coefficients::errorConstant(h / previousStep) : 0.0;
}

} // namespace softbody
