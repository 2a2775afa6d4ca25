// Embedded estimates of a step's local position error: its leading term read off the step
// itself, so that error control judges a step by taking it once instead of three times (whole
// and two halves, error_control.h). Each is the integrator's error constant times the
// derivative its error term holds, that derivative taken from the velocities the step and its
// history left (divided differences):
//
//   backward Euler (Implicit Euler, Projective Dynamics, Vertex Block Descent): x+ = x + h v+
//     makes x + h v + h^2 a where the motion makes x + h v + h^2 a / 2, an error of h^2 x'' / 2,
//     with x'' = (v+ - v) / h: |e| = h |v+ - v| / 2 (exact under a constant acceleration);
//   BDF2: C(w) h^3 x''' (bdf2_formula.h), with x''' twice the second divided difference of
//     v-, v, v+ at t - h_prev, t, t + h; a step without history is backward Euler's.
//
// The estimates are per point and per component (the caller drops held components and points
// in contact, whose velocities a response changed).
#pragma once

#include "softbody/common/state.h"

#include <cstddef>

namespace softbody
{

struct EmbeddedErrorEstimate
{
  /// Point i's local position error [m] of the step of h taken from `start` to `end`.
  Vec3 (*pointError)(const DynamicState& start, const DynamicState& end, double h, std::size_t i);
  /// The constant of its error term for a step of h after one of previousStep, where it
  /// depends on the step ratio; 0 for a step of another order. Null: one constant for all
  /// (ErrorControl::errorConstant).
  double (*constant)(double h, double previousStep);
};

extern const EmbeddedErrorEstimate kBackwardEulerEstimate;
extern const EmbeddedErrorEstimate kBdf2Estimate;

} // namespace softbody
