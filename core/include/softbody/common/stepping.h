// Small pieces every stepper shares: how an interval is split into equal steps, and a timer
// that adds a scope's wall time to a stage's total.
#pragma once

#include "softbody/common/state.h"
#include "softbody/common/simulation.h"  // AdvanceStatus, ProgressCallback

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

/// The advance() loop every CPU stepper shares: equal steps no larger than maxStep that land
/// exactly on endTime, the time taken from the step index (accumulating h would drift), and
/// every `checkInterval` steps and after the last one a divergence check and the progress
/// callback (which may abort). `stepOnce(h, isLast)` advances the state by h.
template <typename StepOnce, typename CheckDivergence>
AdvanceStatus advanceInEqualSteps(DynamicState& state, double maxStep, double endTime,
  const ProgressCallback& progress, unsigned long long checkInterval, const StepOnce& stepOnce,
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
  for (unsigned long long s = 1; s <= steps; ++s)
  {
    stepOnce(h, s == steps);
    state.time = (s == steps) ? endTime : startTime + static_cast<double>(s) * h;
    if (s % checkInterval == 0 || s == steps)
    {
      checkDivergence();
      if (progress && !progress(double(s) / double(steps)))
      {
        return AdvanceStatus::Aborted;
      }
    }
  }
  return AdvanceStatus::Completed;
}

class ScopedStageTimer
{
public:
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
