#include "softbody/massspring/implicit_solve.h"

#include "softbody/common/parallel.h"
#include "softbody/common/stepping.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace softbody
{
namespace
{

constexpr double kArmijo = 1e-4; // sufficient decrease of Phi along a Newton direction
constexpr int kMaxHalvings = 40; // 2^-40: the direction is useless long before

double dot(const std::vector<Vec3>& a, const std::vector<Vec3>& b)
{
  return parallelSum(a.size(), [&](std::size_t i) { return a[i].dot(b[i]); });
}

std::size_t sum(std::size_t a, std::size_t b)
{
  return a + b;
}

} // namespace

ImplicitStepSolver::ImplicitStepSolver(
  IncrementalPotential& potential, const SceneSettings& scene, LineSearch lineSearch)
  : Potential(potential)
  , Settings(scene.implicit)
  , Search(lineSearch)
  , GravityNorm(scene.gravity.norm())
  , Floor(scene.floorEnabled)
  , FloorOrigin(scene.floor.origin)
{
  Filter.normal = scene.floor.normal.normalized();
}

void ImplicitStepSolver::filterGradient()
{
  Filtered.resize(Gradient.size());
  parallelFor(Gradient.size(), 4096, [&](std::size_t i) { Filtered[i] = Filter.apply(i, Gradient[i]); });
  Residual = Potential.residualAcceleration(Filtered);
}

void ImplicitStepSolver::evaluateAtX()
{
  Energy = Potential.evaluate(X, Gradient);
  filterGradient();
}

std::size_t ImplicitStepSolver::capture(std::vector<Vec3>& x, std::vector<PointMotion>& motion) const
{
  return parallelReduce(
    x.size(), 4096, std::size_t{ 0 },
    [&](std::size_t i) -> std::size_t {
      const double depth = (x[i] - FloorOrigin).dot(Filter.normal);
      if (motion[i] != PointMotion::Fixed && depth < 0.0)
      {
        x[i] -= depth * Filter.normal;
        const bool added = motion[i] == PointMotion::Free;
        motion[i] = PointMotion::OnPlane;
        return added ? 1 : 0;
      }
      return 0;
    },
    sum);
}

std::size_t ImplicitStepSolver::holdPointsHeadingIntoTheFloor()
{
  // A free point lying on the floor (put there earlier, then released) that the direction
  // drives into it would bend the search path at any step length, and the bent path need not
  // descend: hold it now, so the direction slides it along the floor instead.
  return parallelReduce(
    X.size(), 4096, std::size_t{ 0 },
    [&](std::size_t i) -> std::size_t {
      if (Filter.motion[i] != PointMotion::Free || !(Direction[i].dot(Filter.normal) < 0.0))
      {
        return 0;
      }
      const double depth = (X[i] - FloorOrigin).dot(Filter.normal);
      const double rounding =
        64.0 * std::numeric_limits<double>::epsilon() * (X[i].norm() + FloorOrigin.norm());
      if (depth > rounding)
      {
        return 0;
      }
      Filter.motion[i] = PointMotion::OnPlane;
      Direction[i] = Filter.apply(i, Direction[i]);
      return 1;
    },
    sum);
}

std::size_t ImplicitStepSolver::release()
{
  return parallelReduce(
    X.size(), 4096, std::size_t{ 0 },
    [&](std::size_t i) -> std::size_t {
      // Held, and Phi drops by lifting it (its gradient points into the floor): let go.
      if (Filter.motion[i] == PointMotion::OnPlane && Gradient[i].dot(Filter.normal) < 0.0)
      {
        Filter.motion[i] = PointMotion::Free;
        return 1;
      }
      return 0;
    },
    sum);
}

bool ImplicitStepSolver::iterate(StepPlan& plan, const DirectionRule& rule, ImplicitConvergence& c)
{
  const Iterate at{ plan, X, Gradient, Filter, Restart, Residual / StartResidual,
    Goal / StartResidual };
  c.linearIterationsTotal += static_cast<unsigned long long>(rule(at, Direction));
  Restart = false;

  ScopedStageTimer timer(plan, Stage::Forces);
  if (Floor && holdPointsHeadingIntoTheFloor() > 0)
  {
    filterGradient();
  }
  double slope = dot(Gradient, Direction);
  if (!(slope < 0.0))
  {
    // The linear solve broke down before making progress: steepest descent, scaled by the
    // inverse masses, is still a descent direction.
    const double h2 = Potential.step() * Potential.step();
    parallelFor(Direction.size(), 4096, [&](std::size_t i) {
      Direction[i] = -(h2 * Potential.inverseMass(i)) * Filtered[i];
    });
    slope = dot(Gradient, Direction);
    if (!(slope < 0.0))
    {
      return false; // zero filtered gradient: nothing left to do
    }
  }
  double alpha = 1.0;
  double trialEnergy = Energy;
  std::size_t captured = 0;
  bool accepted = false;
  for (int halving = 0; halving <= kMaxHalvings && !accepted; ++halving)
  {
    Trial.resize(X.size());
    parallelFor(X.size(), 4096, [&](std::size_t i) { Trial[i] = X[i] + alpha * Direction[i]; });
    double allowed = Search == LineSearch::Armijo ? kArmijo * alpha * slope : 0.0;
    captured = 0;
    if (Floor)
    {
      TrialMotion = Filter.motion;
      captured = capture(Trial, TrialMotion);
      if (captured > 0 && Search == LineSearch::Armijo)
      {
        // The projection bent the path: ask for a decrease along the step actually taken.
        parallelFor(X.size(), 4096, [&](std::size_t i) { TrialGradient[i] = Trial[i] - X[i]; });
        allowed = std::min(0.0, kArmijo * dot(Gradient, TrialGradient));
      }
    }
    trialEnergy = Potential.evaluate(Trial, TrialGradient);
    accepted = trialEnergy <= Energy + allowed;
    if (!accepted)
    {
      alpha *= 0.5;
      ++c.lineSearchHalvings;
    }
  }
  if (!accepted)
  {
    Potential.evaluate(X, TrialGradient); // restore the element data of x
    return false;
  }
  // A decrease of Phi within its rounding and a residual that no longer halves: the iterate
  // sits at the floor of double precision (stiff bodies reach it above small tolerances).
  const bool flatEnergy = Energy - trialEnergy <= 16.0 * std::numeric_limits<double>::epsilon() *
      std::max(std::abs(Energy), std::abs(trialEnergy));
  const double previousResidual = Residual;
  std::swap(X, Trial);
  std::swap(Gradient, TrialGradient);
  Energy = trialEnergy;
  if (captured > 0)
  {
    std::swap(Filter.motion, TrialMotion);
  }
  filterGradient();
  ++c.iterations;
  c.residualHistory.push_back(Residual / Reference);
  return !(flatEnergy && Residual > 0.5 * previousResidual && captured == 0);
}

void ImplicitStepSolver::step(double h, DynamicState& state, StepPlan& plan,
  const DirectionRule& rule, ImplicitConvergence& c)
{
  {
    ScopedStageTimer timer(plan, Stage::Forces);
    Potential.beginStep(state.positions, state.velocities, h);
    TrialGradient.resize(state.positions.size());
    // Two starting points, keep the lower Phi: the explicit prediction y + h^2 g is exact in
    // free fall; y alone is far better for a body resting on the floor (gravity's drift would
    // push its whole bottom through the floor and back).
    double bestEnergy = std::numeric_limits<double>::infinity();
    for (bool withGravity : { true, false })
    {
      Potential.predict(Trial, withGravity);
      TrialMotion.resize(Trial.size());
      for (std::size_t i = 0; i < Trial.size(); ++i)
      {
        TrialMotion[i] = Potential.active()[i] ? PointMotion::Free : PointMotion::Fixed;
      }
      if (Floor)
      {
        capture(Trial, TrialMotion); // the points whose start lies below the floor
      }
      const double energy = Potential.evaluate(Trial, TrialGradient);
      if (energy < bestEnergy)
      {
        bestEnergy = energy;
        std::swap(X, Trial);
        std::swap(Filter.motion, TrialMotion);
      }
      if (!Floor)
      {
        break; // without contact the prediction is always the better start
      }
    }
    evaluateAtX();
  }
  Reference = Potential.referenceAcceleration(GravityNorm);
  Goal = Settings.tolerance * Reference; // 0 (Projective Dynamics): run every iteration
  StartResidual = std::max(Residual, std::numeric_limits<double>::min());
  c.residualHistory.assign(1, Residual / Reference);
  c.iterations = 0;
  Restart = true;
  while (c.iterations < Settings.maxIterations)
  {
    if (Floor)
    {
      ScopedStageTimer timer(plan, Stage::Floor);
      if (release() > 0)
      {
        filterGradient();
      }
    }
    if (Residual <= Goal && Goal > 0.0)
    {
      break;
    }
    if (!iterate(plan, rule, c))
    {
      break;
    }
  }

  c.residual = Residual / Reference;
  c.converged = Goal > 0.0 ? Residual <= Goal : true;
  ++c.steps;
  c.unconvergedSteps += c.converged ? 0 : 1;
  c.iterationsTotal += static_cast<unsigned long long>(c.iterations);

  parallelFor(X.size(), 4096, [&](std::size_t i) {
    if (Filter.motion[i] == PointMotion::Fixed)
    {
      return;
    }
    Vec3 v = (X[i] - state.positions[i]) / h;
    if (Filter.motion[i] == PointMotion::OnPlane)
    {
      // Inelastic contact: a point held on the floor keeps no speed into it.
      v -= std::min(0.0, v.dot(Filter.normal)) * Filter.normal;
    }
    state.velocities[i] = v;
    state.positions[i] = X[i];
  });
}

} // namespace softbody
