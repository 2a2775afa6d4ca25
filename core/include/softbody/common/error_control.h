// Error-controlled time steps for any integrator: the step is chosen so that the local error
// it makes stays within what the user's tolerance allows, from the integrator's own (embedded)
// estimate where it has one, else by step doubling (Richardson).
//
// An embedded estimate reads the local error off the step itself (every integrator but
// Midpoint: integrators/local_error.h), so each try costs one step. Step doubling takes each step of h
// twice, once whole and once as two halves, three steps a try; for an integrator of order p
// the halves' local error is about |x_halves - x_whole| / (2^p - 1) (the largest over the
// points). The tolerance is in metres per simulated second: a step of h may make a position
// error of half of tolerance * h / 1 s (kPositionShare), so the errors a run accumulates over
// a second stay near the tolerance however many steps it takes (error per unit step: the
// global error then scales with the tolerance, where a bound per step would make it grow with
// the step count). A step within it is accepted (the state goes on from the step, or from its
// halves, the more accurate of the two); one above is rejected, the state put back and the step shortened. The next step is
// h * 0.9 (allowed / estimate)^(1/p) (the estimate grows as h^(p+1), the allowance as h),
// between a fifth and twice this one's, never above the largest step (an explicit
// integrator's stability limit, or the user's TimeStep), and the steps end exactly at the
// advance's end time.
//
// Where the motion is not smooth (a contact's first instant) the estimate stops falling as
// h^(p+1): such a step gets a one-time allowance instead (StepJudge). A step that cannot meet
// its allowance even at kMinStepFraction of the interval is accepted and counted
// (StepControlReport::stepsOverTolerance) rather than shrunk without end; a blow-up still
// stops the run through the divergence check.
#pragma once

#include "softbody/common/simulation.h" // AdvanceStatus, ProgressCallback
#include "softbody/common/state.h"
#include "softbody/common/stepping.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>

namespace softbody
{

/// What the controller is asked to meet.
struct ErrorControl
{
  double tolerance = 0.0; ///< [m] per simulated second (> 0)
  int order = 1;          ///< the integrator's order of accuracy (>= 1)
  /// The largest step [s]: an explicit integrator's stable step, the user's TimeStep, or
  /// infinity.
  double maxStep = std::numeric_limits<double>::infinity();
  /// The factor from |x_halves - x_whole| to the halves' error for a step of h after one of
  /// previousStep; null: Richardson's 1 / (2^p - 1), right where both have the same error
  /// constant (a multistep method's whole step and halves do not: bdf2.h).
  double (*halvesErrorFactor)(double h, double previousStep) = nullptr;
  /// The integrator's embedded estimate of the local position error [m] of the step of h it
  /// took from `start` to `end`, the largest over the points not marked in `skip`
  /// (integrators/local_error.h); empty: step doubling.
  std::function<double(const DynamicState& start, const DynamicState& end, double h,
    const std::vector<char>& skip)>
    localError = nullptr;
  /// The constant of the estimate's error term for a step of h after one of previousStep,
  /// where it depends on the step ratio (BDF2's embedded estimate: bdf2_formula.h); 0 for a
  /// step of another order (BDF2's backward-Euler steps). Null: one constant for every step.
  /// The judge tells a non-smooth event from a smooth step by how the estimate falls when the
  /// step is shortened, so it must compare like with like.
  double (*errorConstant)(double h, double previousStep) = nullptr;
};

/// What the controller did in the last advance() (the filter reports it per frame).
struct StepControlReport
{
  /// Each taken once (an embedded estimate) or whole and as two halves (step doubling).
  unsigned long long acceptedSteps = 0;
  unsigned long long rejectedSteps = 0;
  /// Accepted at the smallest step with an estimate above what the tolerance allows.
  unsigned long long stepsOverTolerance = 0;
  /// Accepted as non-smooth events (a contact's first instant: StepJudge).
  unsigned long long eventSteps = 0;
  /// Sum of the accepted steps' error estimates [m]: the error the advance added.
  double estimatedError = 0.0;
  double smallestStep = 0.0, largestStep = 0.0; ///< of the accepted steps [s]
};

/// The part of the tolerance the position errors the estimate sees may take: the velocity
/// errors each step makes become position errors later, as large again on an undamped
/// oscillator (measured: backward Euler's amplitude error 1.5 to 2.4 times the positions'
/// estimate), so half is left for them.
constexpr double kPositionShare = 0.5;

/// The smallest step the controller shortens to, as a fraction of the advance's interval.
/// A first-order step (BDF2's first, which is backward Euler's) errs as h^2 against an
/// allowance that shrinks as h only: from rest under an acceleration a it meets a tolerance
/// tol at h = tol / a, 3e-7 of a 0.1 s frame for 1e-6 m/s under 32 m/s^2.
constexpr double kMinStepFraction = 1.0e-9;
/// The smallest step a non-smooth event is shortened to, as a fraction of the interval: below
/// it the event is accepted over its allowance and counted (stepsOverTolerance).
constexpr double kEventStepFraction = 1.0e-3;

/// The factor the next step is this one's, from the estimate over the allowance.
double nextStepFactor(double estimate, double allowed, int order);

/// Judges each try of a step from its estimate: accepted or not, and the step to try next.
///
/// A smooth motion's estimate falls as h^(p+1) when the step is shortened; across a contact's
/// first instant (an inelastic landing) it falls only as h (the point stops within the step,
/// at a time the step does not resolve), so an allowance per unit step could never be met. A
/// step whose estimate (over its error constant) fell from the rejected try before it at an
/// order below p + 1/2 is such an event: it is allowed the share of the tolerance of the advance's interval (one
/// frame's worth of error in one go, which a step of about tolerance * interval / speed
/// meets), and counted (StepControlReport::eventSteps).
class StepJudge
{
public:
  StepJudge(const ErrorControl& control, double interval);
  struct Verdict
  {
    bool accepted;
    bool overTolerance; ///< accepted at the smallest step above its allowance
    bool event;         ///< judged as a non-smooth event
    double nextStep;    ///< [s]
  };
  /// A try of h after a step of previousStep, whose error was estimated at `estimate`.
  Verdict judge(double h, double previousStep, double estimate);

private:
  const ErrorControl& Control;
  double Interval, MinStep;
  /// The last rejected try of this step: its size and its estimate over its error constant
  /// (0: none, or not comparable).
  double RejectedStep = 0.0, RejectedScaledEstimate = 0.0;
};

/// Empty when `tolerance` [m per s] can be met on a body at `points`; else why not, quoting
/// the value (<= 0, not finite, or below what double precision resolves as far from the origin
/// as the farthest coordinate).
std::string errorToleranceProblem(double tolerance, const std::vector<Vec3>& points);

/// The largest |a_i - b_i| over the points not marked in `skip` (empty: none) [m].
double largestDifference(const std::vector<Vec3>& a, const std::vector<Vec3>& b, const std::vector<char>& skip);

/// Advances `state` to endTime with error-controlled steps. `takeStep(h)` advances the state
/// by one step of h (its time and counters included); `checkDivergence()` throws on a blow-up;
/// `markContacts(mask)` sets mask[i] for the points in contact after a step. Those are left
/// out of the estimate: where a contact holds a point, whole and halves differ by when within
/// the step it began (first order in h, never met by shortening); its neighbours, which feel
/// the contact through their elements, are measured.
/// The controller's proposal is kept in state.proposedStep (a snapshot resumes the same steps).
template <typename TakeStep, typename CheckDivergence, typename MarkContacts>
AdvanceStatus advanceWithErrorControl(DynamicState& state, const ErrorControl& control,
  double endTime, const ProgressCallback& progress, const TakeStep& takeStep,
  const CheckDivergence& checkDivergence, const MarkContacts& markContacts,
  StepControlReport& report)
{
  report = StepControlReport{};
  const double startTime = state.time;
  const double interval = endTime - startTime;
  if (!(interval > 0.0))
  {
    return AdvanceStatus::Completed;
  }
  StepJudge judge(control, interval);
  double proposal = state.proposedStep > 0.0 ? state.proposedStep : interval;
  DynamicState start;
  std::vector<Vec3> whole;
  std::vector<char> inContact;
  while (state.time < endTime)
  {
    const double left = endTime - state.time;
    proposal = std::min(proposal, control.maxStep);
    // The last steps end on endTime: a step that would pass it is cut to it, and one that
    // would leave less than half a step is shared between two.
    double h = proposal;
    const bool last = h >= left * (1.0 - 1e-9);
    if (last)
    {
      h = left;
    }
    else if (h > 0.5 * left)
    {
      h = 0.5 * left;
    }
    start = state;
    takeStep(h);
    inContact.assign(state.positions.size(), 0);
    markContacts(inContact);
    double estimate = 0.0;
    if (control.localError)
    {
      estimate = control.localError(start, state, h, inContact);
    }
    else
    {
      whole = state.positions;
      state = start;
      takeStep(0.5 * h);
      takeStep(0.5 * h);
      markContacts(inContact);
      const double halvesFactor = control.halvesErrorFactor
        ? control.halvesErrorFactor(h, start.previousStep)
        : 1.0 / (std::ldexp(1.0, control.order) - 1.0);
      estimate = largestDifference(state.positions, whole, inContact) * halvesFactor;
    }
    const StepJudge::Verdict verdict = judge.judge(h, start.previousStep, estimate);
    if (!verdict.accepted)
    {
      ++report.rejectedSteps;
      state = start;
      proposal = verdict.nextStep;
      continue;
    }
    ++report.acceptedSteps;
    if (!std::isfinite(estimate))
    {
      checkDivergence(); // a blow-up at the smallest step: stop and say so
    }
    report.stepsOverTolerance += verdict.overTolerance ? 1 : 0;
    report.eventSteps += verdict.event ? 1 : 0;
    report.estimatedError += estimate;
    report.smallestStep = report.acceptedSteps == 1 ? h : std::min(report.smallestStep, h);
    report.largestStep = std::max(report.largestStep, h);
    state.time = last ? endTime : start.time + h; // the halves' sum would round
    // A cut last step says nothing about the step the motion needs: the proposal stands.
    if (!last || verdict.nextStep < h)
    {
      proposal = verdict.nextStep;
    }
    state.proposedStep = proposal;
    if (report.acceptedSteps % kDivergenceCheckInterval == 0 || last)
    {
      checkDivergence();
      if (progress && !progress((state.time - startTime) / interval))
      {
        return AdvanceStatus::Aborted;
      }
    }
  }
  return AdvanceStatus::Completed;
}

} // namespace softbody
