#include "softbody/common/error_control.h"

#include "softbody/common/parallel.h"
#include "softbody/common/validation.h"

namespace softbody
{
namespace
{

constexpr double kSafety = 0.9;
constexpr double kMinFactor = 0.2;
/// Below 1 + sqrt(2), where variable-step BDF2 stops being zero-stable.
constexpr double kMaxFactor = 2.0;
/// Relative rounding of a coordinate times the number of steps' worth of it a tolerance must
/// stand above to be resolved by step doubling.
constexpr double kResolvableRelativeTolerance = 1.0e-12;

} // namespace

double nextStepFactor(double estimate, double allowed, int order)
{
  if (!(estimate > 0.0))
  {
    return estimate == 0.0 ? kMaxFactor : kMinFactor; // exact, or NaN
  }
  const double factor = kSafety * std::pow(allowed / estimate, 1.0 / static_cast<double>(order));
  return std::clamp(factor, kMinFactor, kMaxFactor);
}

StepJudge::StepJudge(const ErrorControl& control, double interval)
  : Control(control)
  , Interval(interval)
  , MinStep(kMinStepFraction * interval)
{
}

StepJudge::Verdict StepJudge::judge(double h, double previousStep, double estimate)
{
  const double p = static_cast<double>(Control.order);
  double allowed = kPositionShare * Control.tolerance * h; // per second of simulated time
  int scaling = Control.order; // the estimate over the allowance grows as h^scaling
  bool event = false;
  const double constant = Control.errorConstant ? Control.errorConstant(h, previousStep) : 1.0;
  const double scaledEstimate = constant > 0.0 && std::isfinite(estimate) ? estimate / constant : 0.0;
  if (RejectedStep > h && RejectedScaledEstimate > 0.0 && scaledEstimate > 0.0)
  {
    const double observedOrder = std::log(RejectedScaledEstimate / scaledEstimate) / std::log(RejectedStep / h);
    if (observedOrder < p + 0.5)
    {
      event = true;
      allowed = std::max(allowed, kPositionShare * Control.tolerance * Interval);
      scaling = 1; // the estimate ~ h, the allowance fixed
    }
  }
  const double factor = nextStepFactor(estimate, allowed, scaling);
  // An event is not shortened below kEventStepFraction of the interval: the contact model is
  // first order in the step there, and a landing's many contacts would otherwise take the
  // run to tiny steps for the length of the contact.
  const double floor = event ? kEventStepFraction * Interval : MinStep;
  if (!(estimate <= allowed) && h > floor)
  {
    RejectedStep = h;
    RejectedScaledEstimate = scaledEstimate;
    return { false, false, event, std::max(floor, h * factor) };
  }
  RejectedStep = 0.0;
  RejectedScaledEstimate = 0.0;
  // After an event the motion is smooth again: the next step starts from this one.
  return { true, !(estimate <= allowed), event, event ? h : h * factor };
}

std::string errorToleranceProblem(double tolerance, const std::vector<Vec3>& points)
{
  double extent = 0.0;
  for (const Vec3& p : points)
  {
    extent = std::max(extent, p.cwiseAbs().maxCoeff());
  }
  if (!(tolerance > 0.0) || !std::isfinite(tolerance))
  {
    return "ErrorTolerance must be a finite distance > 0 in metres per simulated second, got " +
      check::quote(tolerance) + ".";
  }
  const double floor = kResolvableRelativeTolerance * std::max(extent, 1.0e-300);
  if (tolerance < floor)
  {
    return "ErrorTolerance " + check::quote(tolerance) +
      " m per second is below what double precision resolves on this body, whose points lie up to " +
      check::quote(extent) + " m from the origin (positions round to about 1e-16 of that): use at least " +
      check::quote(floor) + ".";
  }
  return "";
}

double largestDifference(const std::vector<Vec3>& a, const std::vector<Vec3>& b, const std::vector<char>& skip)
{
  return parallelReduce(
    a.size(), 4096, 0.0, [&](std::size_t i) { return !skip.empty() && skip[i] ? 0.0 : (a[i] - b[i]).norm(); },
    [](double x, double y) { return std::isnan(x) || std::isnan(y) ? std::numeric_limits<double>::quiet_NaN() : std::max(x, y); });
}

} // namespace softbody
