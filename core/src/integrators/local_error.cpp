#include "softbody/integrators/local_error.h"

#include "softbody/integrators/bdf2_formula.h"



namespace softbody
{
namespace
{

Vec3 backwardEulerPointError(const DynamicState& start, const DynamicState& end, double h, std::size_t i)
{
  return 0.5 * h * (end.velocities[i] - start.velocities[i]);
}

Vec3 bdf2PointError(const DynamicState& start, const DynamicState& end, double h, std::size_t i)
{
  if (!isBdf2Step(start, h))
  {
    return backwardEulerPointError(start, end, h, i);
  }
  const double hPrevious = start.previousStep;
  const Vec3 slopeBefore = (start.velocities[i] - start.previousVelocities[i]) / hPrevious;
  const Vec3 slopeAfter = (end.velocities[i] - start.velocities[i]) / h;
  const Vec3 thirdDerivative = 2.0 * (slopeAfter - slopeBefore) / (h + hPrevious);
  return Bdf2Coefficients::errorConstant(h / hPrevious) * h * h * h * thirdDerivative;
}

/// Verlet's step of h after one of hp errs by h x''' (hp^2/8 - h^2/6) in position and by
/// x''' (hp^2 - h^2)/8 in its staggered velocity, which the next drift (of about h) adds to the
/// position times h: h x''' (hp^2/4 - 7 h^2/24) in all, h^3 x''' / 24 at a constant step. The
/// estimate is the constant step's. A change of step adds a transient (the kick is centred off
/// the step's start): 5.5 times as much at a doubled step, and after a shorter one a part
/// h hp^2 x''' / 4 that no shortening removes. Weighted in, nearly every grown step was
/// rejected and a shortened retry could never meet its allowance; left out, the achieved
/// error is measured against the tolerance on the lab's scenes (bench_error_control.cpp).
constexpr double kVerletErrorConstant = 1.0 / 24.0;

bool hasVerletHistory(const DynamicState& start, const DynamicState& end, std::size_t i)
{
  return start.previousStep > 0.0 && i < start.previousAccelerations.size() && i < end.previousAccelerations.size();
}

Vec3 verletPointError(const DynamicState& start, const DynamicState& end, double h, std::size_t i)
{
  if (!hasVerletHistory(start, end, i))
  {
    // The first step (the half kick from v(t)) has no jerk to read: judged as a first-order
    // step, which keeps it short until the history exists.
    return backwardEulerPointError(start, end, h, i);
  }
  const Vec3 jerk = (end.previousAccelerations[i] - start.previousAccelerations[i]) / start.previousStep;
  return kVerletErrorConstant * h * h * h * jerk;
}

/// 0 for the first step, of another order.
double verletEstimateConstant(double, double previousStep)
{
  return previousStep > 0.0 ? kVerletErrorConstant : 0.0;
}

} // namespace

const EmbeddedErrorEstimate kFirstOrderEstimate{ backwardEulerPointError, nullptr };
const EmbeddedErrorEstimate kVerletEstimate{ verletPointError, verletEstimateConstant };
const EmbeddedErrorEstimate kBdf2Estimate{ bdf2PointError, bdf2EstimateConstant };

} // namespace softbody
