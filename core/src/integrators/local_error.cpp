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

} // namespace

const EmbeddedErrorEstimate kBackwardEulerEstimate{ backwardEulerPointError, nullptr };
const EmbeddedErrorEstimate kBdf2Estimate{ bdf2PointError, bdf2EstimateConstant };

} // namespace softbody
