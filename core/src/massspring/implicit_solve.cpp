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
/// Contact-set rounds per step: each re-solves from the last answer; two suffice unless
/// contacts flicker between release and penetration.
constexpr int kMaxContactRounds = 8;

double dot(const std::vector<Vec3>& a, const std::vector<Vec3>& b)
{
  return parallelSum(a.size(), [&](std::size_t i) { return a[i].dot(b[i]); });
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

void ImplicitStepSolver::evaluateAtX()
{
  Energy = Potential.evaluate(X, Gradient);
  Filtered.resize(Gradient.size());
  parallelFor(Gradient.size(), 4096, [&](std::size_t i) { Filtered[i] = Filter.apply(i, Gradient[i]); });
  Residual = Potential.residualAcceleration(Filtered);
}

std::size_t ImplicitStepSolver::updateContacts(bool release)
{
  return parallelReduce(
    X.size(), 4096, std::size_t{ 0 },
    [&](std::size_t i) -> std::size_t {
      if (Filter.motion[i] == PointMotion::OnPlane)
      {
        // Held: Phi would drop by lifting it (its gradient points into the floor) -> let go.
        if (release && Gradient[i].dot(Filter.normal) < 0.0)
        {
          Filter.motion[i] = PointMotion::Free;
          return 1;
        }
        return 0;
      }
      const double depth = (X[i] - FloorOrigin).dot(Filter.normal);
      if (Filter.motion[i] == PointMotion::Free && depth < 0.0)
      {
        X[i] -= depth * Filter.normal;
        Filter.motion[i] = PointMotion::OnPlane;
        return 1;
      }
      return 0;
    },
    [](std::size_t a, std::size_t b) { return a + b; });
}

void ImplicitStepSolver::iterate(StepPlan& plan, const DirectionRule& rule, ImplicitConvergence& c)
{
  int iterations = 0;
  while (iterations < Settings.maxIterations && !(Residual <= Goal && Goal > 0.0))
  {
    {
      ScopedStageTimer timer(plan, Stage::LinearSolve);
      const Iterate at{ X, Gradient, Filter, Restart, Residual / Reference, Goal / Reference };
      c.linearIterationsTotal += static_cast<unsigned long long>(rule(at, Direction));
      Restart = false;
    }
    ScopedStageTimer timer(plan, Stage::Forces);
    double slope = dot(Gradient, Direction);
    if (!(slope < 0.0))
    {
      // The linear solve broke down before making progress: steepest descent, scaled by the
      // inverse masses, is still a descent direction.
      parallelFor(Direction.size(), 4096, [&](std::size_t i) {
        const double w = Potential.inverseMass(i);
        Direction[i] = -(Potential.step() * Potential.step() * w) * Filtered[i];
      });
      slope = dot(Gradient, Direction);
      if (!(slope < 0.0))
      {
        return; // zero filtered gradient: nothing to do
      }
    }
    double alpha = 1.0;
    double trialEnergy = Energy;
    bool accepted = false;
    for (int halving = 0; halving <= kMaxHalvings && !accepted; ++halving)
    {
      Trial.resize(X.size());
      parallelFor(X.size(), 4096, [&](std::size_t i) { Trial[i] = X[i] + alpha * Direction[i]; });
      trialEnergy = Potential.evaluate(Trial, TrialGradient);
      const double allowed = Search == LineSearch::Armijo ? kArmijo * alpha * slope : 0.0;
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
      return;
    }
    // A decrease of Phi within its rounding and a residual that no longer halves: the iterate
    // sits at the floor of double precision (stiff bodies reach it above small tolerances);
    // more iterations would only spin.
    const bool flatEnergy = Energy - trialEnergy <= 16.0 * std::numeric_limits<double>::epsilon() *
        std::max(std::abs(Energy), std::abs(trialEnergy));
    const double previousResidual = Residual;
    std::swap(X, Trial);
    std::swap(Gradient, TrialGradient);
    Energy = trialEnergy;
    parallelFor(Gradient.size(), 4096, [&](std::size_t i) { Filtered[i] = Filter.apply(i, Gradient[i]); });
    Residual = Potential.residualAcceleration(Filtered);
    ++iterations;
    ++c.iterations;
    c.residualHistory.push_back(Residual / Reference);
    if (flatEnergy && Residual > 0.5 * previousResidual)
    {
      return;
    }
  }
}

void ImplicitStepSolver::step(double h, DynamicState& state, StepPlan& plan,
  const DirectionRule& rule, ImplicitConvergence& c)
{
  {
    ScopedStageTimer timer(plan, Stage::Forces);
    Potential.beginStep(state.positions, state.velocities, h);
    Potential.predict(X);
    Filter.motion.resize(X.size());
    for (std::size_t i = 0; i < X.size(); ++i)
    {
      Filter.motion[i] = Potential.active()[i] ? PointMotion::Free : PointMotion::Fixed;
    }
    if (Floor)
    {
      updateContacts(false); // start with the points whose prediction ends below the floor
    }
    evaluateAtX();
  }
  Reference = Potential.referenceAcceleration(GravityNorm);
  Goal = Settings.tolerance * Reference; // 0 (Projective Dynamics): run every iteration
  c.residualHistory.assign(1, Residual / Reference);
  c.iterations = 0;
  Restart = true;
  for (int round = 0; round < kMaxContactRounds; ++round)
  {
    iterate(plan, rule, c);
    if (!Floor)
    {
      break;
    }
    ScopedStageTimer timer(plan, Stage::Floor);
    if (updateContacts(true) == 0)
    {
      break;
    }
    Restart = true;
    evaluateAtX();
    c.residualHistory.push_back(Residual / Reference);
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
