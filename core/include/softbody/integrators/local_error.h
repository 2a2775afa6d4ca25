// Embedded estimates of a step's local position error: its leading term read off the step
// itself, so that error control judges a step by taking it once instead of three times (whole
// and two halves, error_control.h). Each is the integrator's error constant times the
// derivative its error term holds, that derivative taken from the velocities the step and its
// history left (divided differences):
//
//   backward Euler (Implicit Euler, Projective Dynamics, Vertex Block Descent): x+ = x + h v+
//     makes x + h v + h^2 a where the motion makes x + h v + h^2 a / 2, an error of h^2 x'' / 2,
//     with x'' = (v+ - v) / h: |e| = h |v+ - v| / 2 (exact under a constant acceleration);
//   explicit Euler: x+ = x + h v errs by -h^2 x''/2, the same h |v+ - v| / 2. (Not
//     Euler-Cromer: its positions are leapfrog's, second order, so this first-order term
//     overstates its error by an order of magnitude on an oscillating body; it doubles its
//     steps.)
//   BDF2: C(w) h^3 x''' (bdf2_formula.h), with x''' twice the second divided difference of
//     v-, v, v+ at t - h_prev, t, t + h; a step without history is backward Euler's;
//   Verlet (leapfrog, velocity staggered by half a step): the error in position plus h times
//     that of the staggered velocity, which the next drift adds to it, h^3 x''' / 24 at a
//     constant step, without the transient a change of step adds (local_error.cpp); x''' is
//     the difference of the last two kicks' accelerations (DynamicState::previousAccelerations)
//     over the step before, the jerk half a step back. A first step, without that history, is
//     judged as a first-order one.
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

/// h |v+ - v| / 2: backward Euler's and explicit Euler's.
extern const EmbeddedErrorEstimate kFirstOrderEstimate;
extern const EmbeddedErrorEstimate kVerletEstimate;
extern const EmbeddedErrorEstimate kBdf2Estimate;

} // namespace softbody
