#include "softbody/massspring/implicit_solve.h"

#include "softbody/collision/coulomb_friction.h"

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
/// A free point closer to the floor than this fraction of its approach in a full step is held
/// on the floor before the line search (see holdPointsOnTheFloorPath).
constexpr double kHoldFraction = 1e-3;
/// Direction solves per iteration while new points get held (then the line search's ratio
/// test takes care of the rest).
constexpr int kMaxHoldSolves = 3;
/// Step halvings tried along the path bent by the floor before the straight one.
constexpr int kBentHalvings = 8;

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
  , Floor(scene.floorActive())
  , FloorOrigin(scene.floor.origin)
  , Friction(scene.collisions)
{
  Filter.normal = scene.floor.normal.normalized();
}

void ImplicitStepSolver::filterGradient()
{
  Filtered.resize(Gradient.size());
  parallelFor(Gradient.size(), 4096, [&](std::size_t i) { Filtered[i] = Filter.apply(i, Gradient[i]); });
  Residual = Potential.residualAcceleration(Filtered);
}

double ImplicitStepSolver::filteredResidual(
  const std::vector<Vec3>& gradient, const std::vector<PointMotion>& motion)
{
  const MotionFilter filter{ motion, Filter.normal, Filter.heldAxes };
  Scratch.resize(gradient.size());
  parallelFor(gradient.size(), 4096, [&](std::size_t i) { Scratch[i] = filter.apply(i, gradient[i]); });
  return Potential.residualAcceleration(Scratch);
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

std::size_t ImplicitStepSolver::holdPointsOnTheFloorPath()
{
  // A free point on the floor (or within a tiny fraction of this step above it) that the
  // direction drives into it would stop every step length at almost nothing: hold it now, so
  // the direction slides it along the floor instead.
  return parallelReduce(
    X.size(), 4096, std::size_t{ 0 },
    [&](std::size_t i) -> std::size_t {
      const double approach = -Direction[i].dot(Filter.normal);
      if (Filter.motion[i] != PointMotion::Free || !(approach > 0.0))
      {
        return 0;
      }
      const double depth = (X[i] - FloorOrigin).dot(Filter.normal);
      if (depth > kHoldFraction * approach)
      {
        return 0;
      }
      Filter.motion[i] = PointMotion::OnPlane;
      Direction[i] = Filter.apply(i, Direction[i]);
      return 1;
    },
    sum);
}

double ImplicitStepSolver::floorReach() const
{
  // The ratio test of active-set methods: the largest alpha <= 1 at which no free point has
  // crossed the floor.
  return parallelReduce(
    X.size(), 4096, 1.0,
    [&](std::size_t i) {
      const double approach = -Direction[i].dot(Filter.normal);
      if (Filter.motion[i] != PointMotion::Free || !(approach > 0.0))
      {
        return 1.0;
      }
      return std::max(0.0, (X[i] - FloorOrigin).dot(Filter.normal)) / approach;
    },
    [](double a, double b) { return std::min(a, b); });
}

bool ImplicitStepSolver::withinFrictionCone(const Vec3& force) const
{
  const double normal = force.dot(Filter.normal);
  return normal > 0.0 && (force - normal * Filter.normal).norm() <= Friction.staticFriction * normal;
}

std::size_t ImplicitStepSolver::release()
{
  return parallelReduce(
    X.size(), 4096, std::size_t{ 0 },
    [&](std::size_t i) -> std::size_t {
      // Held, and Phi drops by lifting it (its gradient points into the floor): let go.
      // (Only when the pull is above the tolerance: a point whose pull is within it would be
      // put back at once, and each round trip costs a solve.)
      if (Filter.motion[i] == PointMotion::OnPlane &&
        Gradient[i].dot(Filter.normal) * Potential.inverseMass(i) < -Goal)
      {
        Filter.motion[i] = PointMotion::Free;
        return 1;
      }
      // Stuck by static friction, and the force that takes has left the friction cone (it
      // is pulled off the floor, or along it harder than staticFriction times the push): it
      // slides from here on, in this solve.
      if (Stuck[i] && !withinFrictionCone(Gradient[i]))
      {
        Stuck[i] = 0;
        Filter.motion[i] = PointMotion::OnPlane;
        return 1;
      }
      return 0;
    },
    sum);
}

bool ImplicitStepSolver::iterate(StepPlan& plan, const DirectionRule& rule, ImplicitConvergence& c)
{
  // The direction, solved again while it drives points lying on the floor into it: holding
  // them changes the system (cutting their motion out of a stiff body's direction afterwards
  // would leave a direction that strains it enormously).
  for (int solve = 0; solve < kMaxHoldSolves; ++solve)
  {
    const Iterate at{ plan, X, Gradient, Filter, Restart, Residual / StartResidual,
      Goal / StartResidual };
    c.linearIterationsTotal += static_cast<unsigned long long>(rule(at, Direction));
    Restart = false;
    ScopedStageTimer timer(plan, Stage::Floor);
    if (!Floor || holdPointsOnTheFloorPath() == 0)
    {
      break;
    }
    filterGradient();
  }

  ScopedStageTimer timer(plan, Stage::Forces);
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
  const double reach = Floor ? floorReach() : 1.0; // before a free point crosses the floor
  // First the full step with the points that would cross the floor stopped on it (a bent
  // path: the Armijo test then asks for a decrease along the displacement actually taken).
  // That is what lets a body settle onto the floor in a few iterations; a stiff body pressed
  // against it can find no such step (stopping a few points strains it enormously), and then
  // the search backtracks along the straight path from the longest step that crosses nothing.
  double alpha = 1.0;
  double trialEnergy = Energy;
  bool accepted = false;
  std::size_t captured = 0;
  for (int halving = 0; Floor && reach < 1.0 && halving < kBentHalvings && !accepted; ++halving)
  {
    Trial.resize(X.size());
    parallelFor(X.size(), 4096, [&](std::size_t i) { Trial[i] = X[i] + alpha * Direction[i]; });
    TrialMotion = Filter.motion;
    captured = capture(Trial, TrialMotion);
    Scratch.resize(X.size());
    parallelFor(X.size(), 4096, [&](std::size_t i) { Scratch[i] = Trial[i] - X[i]; });
    const double allowed =
      Search == LineSearch::Armijo ? std::min(0.0, kArmijo * dot(Gradient, Scratch)) : 0.0;
    trialEnergy = Potential.evaluate(Trial, TrialGradient);
    accepted = trialEnergy <= Energy + allowed;
    if (accepted)
    {
      std::swap(Filter.motion, TrialMotion);
    }
    else
    {
      alpha *= 0.5;
      ++c.lineSearchHalvings;
    }
  }
  alpha = reach;
  for (int halving = 0; halving <= kMaxHalvings && !accepted; ++halving)
  {
    Trial.resize(X.size());
    parallelFor(X.size(), 4096, [&](std::size_t i) { Trial[i] = X[i] + alpha * Direction[i]; });
    const double allowed = Search == LineSearch::Armijo ? kArmijo * alpha * slope : 0.0;
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
    // Near the solution of a stiff body Phi's changes drown in its rounding (its terms are
    // ~1e16 times the last iterations' decrease), and no step length passes the test. The
    // longest step is then taken if it lowers the residual, which stays measurable there.
    alpha = reach;
    parallelFor(X.size(), 4096, [&](std::size_t i) { Trial[i] = X[i] + alpha * Direction[i]; });
    trialEnergy = Potential.evaluate(Trial, TrialGradient);
    const double trialResidual = filteredResidual(TrialGradient, Filter.motion);
    const bool withinRounding = std::abs(trialEnergy - Energy) <=
      1024.0 * std::numeric_limits<double>::epsilon() * std::abs(Energy);
    if (!(withinRounding && trialResidual < 0.5 * Residual))
    {
      Potential.evaluate(X, TrialGradient); // restore the element data of x
      return false;
    }
  }
  // A decrease of Phi within its rounding and a residual that no longer halves: the iterate
  // sits at the floor of double precision (stiff bodies reach it above small tolerances).
  const bool flatEnergy = Energy - trialEnergy <= 16.0 * std::numeric_limits<double>::epsilon() *
      std::max(std::abs(Energy), std::abs(trialEnergy));
  const double previousResidual = Residual;
  std::swap(X, Trial);
  std::swap(Gradient, TrialGradient);
  Energy = trialEnergy;
  // The points that stopped the step reached the floor: from now on they slide along it.
  const std::size_t landed = captured +
    ((Floor && alpha == reach && reach < 1.0) ? capture(X, Filter.motion) : 0);
  if (landed > captured)
  {
    Energy = Potential.evaluate(X, Gradient); // they moved by rounding onto the plane
  }
  filterGradient();
  ++c.iterations;
  c.residualHistory.push_back(Residual / Reference);
  return !(flatEnergy && Residual > 0.5 * previousResidual && landed == 0);
}

void ImplicitStepSolver::step(double h, DynamicState& state, StepPlan& plan,
  const DirectionRule& rule, ImplicitConvergence& c)
{
  {
    ScopedStageTimer timer(plan, Stage::Forces);
    Potential.beginStep(state.positions, state.velocities, h, state.time);
    Filter.heldAxes = Potential.heldAxes();
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
    Stuck.resize(X.size(), 0);
    for (std::size_t i = 0; Floor && i < X.size(); ++i)
    {
      if (Stuck[i])
      {
        X[i] = state.positions[i]; // where static friction holds it (on the floor)
        Filter.motion[i] = PointMotion::Fixed;
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
    if (Filter.motion[i] == PointMotion::Fixed && !Stuck[i])
    {
      return; // pinned
    }
    state.velocities[i] = endVelocity(i, h, state.positions);
    state.positions[i] = X[i];
  });
}

Vec3 ImplicitStepSolver::endVelocity(std::size_t i, double h, const std::vector<Vec3>& start)
{
  const Vec3& n = Filter.normal;
  if (Stuck[i])
  {
    // Held in place through the solve (release() frees it during the solve once the force it
    // takes leaves the friction cone; this is the final check).
    Stuck[i] = withinFrictionCone(Gradient[i]) ? 1 : 0;
    return Vec3::Zero();
  }
  Vec3 v = (X[i] - start[i]) / h;
  if (Filter.motion[i] != PointMotion::OnPlane)
  {
    return v;
  }
  // Inelastic contact: a point held on the floor keeps no speed into it.
  v -= std::min(0.0, v.dot(n)) * n;
  // Coulomb friction on its slip (the floor inside the solve only holds points on the plane):
  // the plane's push over the step is the normal part of the potential's gradient at the
  // solution (the force the filter keeps the point from following), as a speed h F_n / m. The
  // slip of the step changes with the velocity; a point that sticks stays where the step began
  // and is held there through the next solves (Stuck) rather than put back after each, which
  // would strain a stiff body anew every step.
  const double push = h * std::max(0.0, Gradient[i].dot(n)) * Potential.inverseMass(i);
  bool sticks = false;
  const Vec3 change = coulombFrictionChange(v - v.dot(n) * n, push, Friction, sticks);
  X[i] += h * change;
  Stuck[i] = sticks ? 1 : 0;
  return v + change;
}

} // namespace softbody
