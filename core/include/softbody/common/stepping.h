// Small pieces every stepper shares: how an interval is split into equal steps, the advance()
// loop, and a timer that adds a scope's wall time to a stage of the step plan.
#pragma once

#include "softbody/common/state.h"
#include "softbody/common/simulation.h"  // AdvanceStatus, ProgressCallback

#include <algorithm>
#include <chrono>
#include <cmath>

namespace softbody
{

/// Number of equal steps no larger than maxStep that cover `interval` (> 0). The 1e-9 slack
/// keeps an interval that is a whole number of steps (up to rounding) from getting one more.
inline unsigned long long equalStepCount(double interval, double maxStep)
{
  const double steps = std::ceil(interval / maxStep * (1.0 - 1e-9));
  return steps < 1.0 ? 1ULL : static_cast<unsigned long long>(steps);
}

/// How often (in steps) every stepper checks for divergence and reports progress; a GPU
/// stepper runs the steps between two checks as one batch.
constexpr unsigned long long kDivergenceCheckInterval = 16;

/// The advance() loop every stepper shares (CPU mass-spring, GPU mass-spring, PBD/XPBD): equal
/// steps no larger than maxStep that land exactly on endTime, run in batches that end every
/// kDivergenceCheckInterval steps and at the last step; after each batch the time is set from
/// the step index (accumulating h would drift), `checkDivergence()` runs and the progress
/// callback (which may abort) is called.
/// `runSteps(h, count, endsWithLastStep)` advances the state by `count` steps of h;
/// `endsWithLastStep` says that the batch's last step is the last one of this advance() (PBD
/// records the convergence of that step only).
template <typename RunSteps, typename CheckDivergence>
AdvanceStatus advanceInEqualSteps(DynamicState& state, double maxStep, double endTime,
  const ProgressCallback& progress, const RunSteps& runSteps,
  const CheckDivergence& checkDivergence)
{
  const double interval = endTime - state.time;
  if (!(interval > 0.0))
  {
    return AdvanceStatus::Completed;
  }
  const unsigned long long steps = equalStepCount(interval, maxStep);
  const double h = interval / static_cast<double>(steps);
  const double startTime = state.time;
  unsigned long long done = 0;
  while (done < steps)
  {
    const unsigned long long batchEnd =
      std::min(steps, (done / kDivergenceCheckInterval + 1) * kDivergenceCheckInterval);
    runSteps(h, batchEnd - done, batchEnd == steps);
    done = batchEnd;
    state.time = (done == steps) ? endTime : startTime + static_cast<double>(done) * h;
    state.previousStep = h;
    checkDivergence();
    if (progress && !progress(double(done) / double(steps)))
    {
      return AdvanceStatus::Aborted;
    }
  }
  return AdvanceStatus::Completed;
}

/// Adapts a one-step function `stepOnce(h, isLastStep)` to advanceInEqualSteps' batches.
template <typename StepOnce>
auto oneStepAtATime(const StepOnce& stepOnce)
{
  return [&stepOnce](double h, unsigned long long count, bool endsWithLastStep) {
    for (unsigned long long s = 1; s <= count; ++s)
    {
      stepOnce(h, endsWithLastStep && s == count);
    }
  };
}

/// Adds a scope's wall time to a stage's total in the step plan.
class ScopedStageTimer
{
public:
  ScopedStageTimer(StepPlan& plan, Stage stage)
    : ScopedStageTimer(plan.seconds(stage))
  {
  }
  explicit ScopedStageTimer(double& seconds)
    : Seconds(seconds)
    , Start(std::chrono::steady_clock::now())
  {
  }
  ~ScopedStageTimer()
  {
    Seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - Start).count();
  }
  ScopedStageTimer(const ScopedStageTimer&) = delete;
  ScopedStageTimer& operator=(const ScopedStageTimer&) = delete;

private:
  double& Seconds;
  std::chrono::steady_clock::time_point Start;
};

} // namespace softbody
