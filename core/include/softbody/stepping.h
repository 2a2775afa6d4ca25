// Small pieces every stepper shares: how an interval is split into equal steps, and a timer
// that adds a scope's wall time to a stage's total.
#pragma once

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
