#include "softbody/massspring/static_solve.h"

#include "softbody/common/errors.h"

#include <algorithm>

namespace softbody
{

std::string staticHoldProblem(const std::vector<Vec3>& positions, const PointMasses& masses)
{
  std::vector<Vec3> fixed;
  for (std::size_t i = 0; i < positions.size(); ++i)
  {
    if (masses.inverseMass[i] == 0.0)
    {
      fixed.push_back(positions[i]);
    }
  }
  const std::string remedy = " Hold it where it is supported: a Fixed Soft Body Condition on "
                             "that region (or PinnedPointsArray), or use Implicit Euler, which "
                             "needs no support.";
  if (fixed.size() < 3)
  {
    return "Integrator Static needs a body held still, but it has " +
      std::to_string(fixed.size()) + " fixed points: a body held at fewer than three points can "
      "move or turn freely and has no static equilibrium." + remedy;
  }
  // Three points not on one line: the farthest from the first, then the farthest from their
  // line, compared with the body's size.
  double extent = 0.0;
  for (const Vec3& p : positions)
  {
    extent = std::max(extent, (p - positions.front()).norm());
  }
  const Vec3& a = fixed.front();
  const auto far = std::max_element(fixed.begin(), fixed.end(),
    [&](const Vec3& p, const Vec3& q) { return (p - a).squaredNorm() < (q - a).squaredNorm(); });
  const Vec3 axis = (*far - a).normalized();
  double offLine = 0.0;
  for (const Vec3& p : fixed)
  {
    offLine = std::max(offLine, ((p - a) - (p - a).dot(axis) * axis).norm());
  }
  if (!((*far - a).norm() > 1e-9 * extent) || !(offLine > 1e-9 * extent))
  {
    return "Integrator Static needs a body held still, but its " + std::to_string(fixed.size()) +
      " fixed points lie on one line: the body can turn about it and has no static "
      "equilibrium." + remedy;
  }
  return {};
}

StaticStepper::StaticStepper(const Topology& topology, const BodyElements& elements,
  const PointMasses& masses, const std::vector<Vec3>& restPositions, const SceneSettings& scene,
  const std::vector<Vec3>& positions)
{
  if (const std::string problem = staticHoldProblem(positions, masses); !problem.empty())
  {
    throw InvalidInputError(problem);
  }
  BodyElements undamped = elements;
  Network = *elements.network;
  std::fill(Network.springDamping.begin(), Network.springDamping.end(), 0.0);
  std::fill(Network.volumeDamping.begin(), Network.volumeDamping.end(), 0.0);
  undamped.network = &Network;
  if (elements.tets)
  {
    Tets = *elements.tets;
    Tets.damped = false;
    undamped.tets = &Tets;
  }
  Newton = std::make_unique<ImplicitEulerStepper>(topology, undamped, masses, restPositions, scene, true);
}

void StaticStepper::step(double h, DynamicState& state, StepPlan& plan)
{
  std::fill(state.velocities.begin(), state.velocities.end(), Vec3::Zero());
  Newton->step(h, state, plan);
  std::fill(state.velocities.begin(), state.velocities.end(), Vec3::Zero());
}

} // namespace softbody
