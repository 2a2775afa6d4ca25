#include "softbody/massspring/implicit_solve.h"

#include "softbody/collision/coulomb_friction.h"

#include "softbody/common/parallel.h"
#include "softbody/common/stepping.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <optional>

namespace softbody
{
namespace
{

constexpr double kArmijo = 1e-4; // sufficient decrease of Phi along a Newton direction
constexpr int kMaxHalvings = 40; // 2^-40: the direction is useless long before
/// A free point closer to its plane than this fraction of its approach in a full step is held
/// on it before the line search (see holdPointsOnThePath).
constexpr double kHoldFraction = 1e-3;
/// Direction solves per iteration while new points get held (then the line search's ratio
/// test takes care of the rest).
constexpr int kMaxHoldSolves = 3;
/// Solves with the loads of bodies' contacts carried over (see step()). Each pass is a whole
/// solve, and the exchange of pushes and faces is not a contraction: on the tori of
/// MassSpringCollisions.ImplicitIntegratorsLandABodyOnABody... the most tets inverted in a
/// frame (Implicit Euler / Projective Dynamics) were 29 / 47 after one pass, 12 / 24 after two,
/// 17 / 7 after three and 9 / 16 after four. Two more than halves one pass's at one solve more.
constexpr int kBodyContactPasses = 2;
/// Step halvings tried along the path bent by the contacts before the straight one.
constexpr int kBentHalvings = 8;
/// The most friction may move a point after the solve, as a fraction of its elements' size
/// (see step()): a quarter strains them by at most that much.
constexpr double kFrictionShiftFraction = 0.25;

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
  , Planes(scene.floorActive() ? std::optional<FloorPlane>(scene.floor) : std::nullopt)
  , Friction(scene.collisions)
{
  Filter.planes = &Planes;
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
  const MotionFilter filter{ motion, Filter.planes, Filter.heldAxes };
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
      const double depth = Planes.depth(i, x[i]);
      if (motion[i] != PointMotion::Fixed && depth < 0.0)
      {
        x[i] -= depth * Planes.of(i).normal;
        const bool added = motion[i] == PointMotion::Free;
        motion[i] = PointMotion::OnPlane;
        return added ? 1 : 0;
      }
      return 0;
    },
    sum);
}

std::size_t ImplicitStepSolver::holdPointsOnThePath()
{
  // A free point on its plane (or within a tiny fraction of this step in front of it) that the
  // direction drives into it would stop every step length at almost nothing: hold it now, so
  // the direction slides it along the plane instead.
  return parallelReduce(
    X.size(), 4096, std::size_t{ 0 },
    [&](std::size_t i) -> std::size_t {
      if (Filter.motion[i] != PointMotion::Free || !Planes.has(i))
      {
        return 0;
      }
      const double approach = -Direction[i].dot(Planes.of(i).normal);
      if (!(approach > 0.0))
      {
        return 0;
      }
      const double depth = Planes.depth(i, X[i]);
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

double ImplicitStepSolver::contactReach() const
{
  // The ratio test of active-set methods: the largest alpha <= 1 at which no free point has
  // crossed its plane.
  return parallelReduce(
    X.size(), 4096, 1.0,
    [&](std::size_t i) {
      if (Filter.motion[i] != PointMotion::Free || !Planes.has(i))
      {
        return 1.0;
      }
      const double approach = -Direction[i].dot(Planes.of(i).normal);
      if (!(approach > 0.0))
      {
        return 1.0;
      }
      return std::max(0.0, Planes.depth(i, X[i])) / approach;
    },
    [](double a, double b) { return std::min(a, b); });
}

bool ImplicitStepSolver::withinFrictionCone(std::size_t i, const Vec3& force) const
{
  const Vec3& n = Planes.of(i).normal;
  const double normal = force.dot(n);
  return normal > 0.0 && (force - normal * n).norm() <= Friction.staticFriction * normal;
}

std::size_t ImplicitStepSolver::release()
{
  return parallelReduce(
    X.size(), 4096, std::size_t{ 0 },
    [&](std::size_t i) -> std::size_t {
      // Held, and Phi drops by lifting it (its gradient points into the plane): let go.
      // (Only when the pull is above the tolerance: a point whose pull is within it would be
      // put back at once, and each round trip costs a solve.)
      if (Filter.motion[i] == PointMotion::OnPlane &&
        Gradient[i].dot(Planes.of(i).normal) * Potential.inverseMass(i) < -Goal)
      {
        Filter.motion[i] = PointMotion::Free;
        return 1;
      }
      // Stuck by static friction, and the force that takes has left the friction cone (it
      // is pulled off its plane, or along it harder than staticFriction times the push): it
      // slides from here on, in this solve.
      if (Stuck[i] && !withinFrictionCone(i, Gradient[i]))
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
  // The direction, solved again while it drives points lying on their plane into it: holding
  // them changes the system (cutting their motion out of a stiff body's direction afterwards
  // would leave a direction that strains it enormously).
  for (int solve = 0; solve < kMaxHoldSolves; ++solve)
  {
    const Iterate at{ plan, X, Gradient, Filter, Restart, Residual / StartResidual,
      Goal / StartResidual };
    c.linearIterationsTotal += static_cast<unsigned long long>(rule(at, Direction));
    Restart = false;
    ScopedStageTimer timer(plan, Stage::Floor);
    if (!contacts() || holdPointsOnThePath() == 0)
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
  const double reach = contacts() ? contactReach() : 1.0; // before a free point crosses its plane
  // First the full step with the points that would cross their plane stopped on it (a bent
  // path: the Armijo test then asks for a decrease along the displacement actually taken).
  // That is what lets a body settle onto the floor in a few iterations; a stiff body pressed
  // against it can find no such step (stopping a few points strains it enormously), and then
  // the search backtracks along the straight path from the longest step that crosses nothing.
  double alpha = 1.0;
  double trialEnergy = Energy;
  bool accepted = false;
  std::size_t captured = 0;
  for (int halving = 0; contacts() && reach < 1.0 && halving < kBentHalvings && !accepted; ++halving)
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
  // The points that stopped the step reached their plane: from now on they slide along it.
  const std::size_t landed = captured +
    ((contacts() && alpha == reach && reach < 1.0) ? capture(X, Filter.motion) : 0);
  if (landed > captured)
  {
    Energy = Potential.evaluate(X, Gradient); // they moved by rounding onto the plane
  }
  filterGradient();
  ++c.iterations;
  c.residualHistory.push_back(Residual / Reference);
  return !(flatEnergy && Residual > 0.5 * previousResidual && landed == 0);
}

void ImplicitStepSolver::solve(double h, const DynamicState& state, StepPlan& plan,
  const DirectionRule& rule, ImplicitConvergence& c)
{
  {
    ScopedStageTimer timer(plan, Stage::Forces);
    Potential.beginStep(state.positions, state.velocities, h, state.time);
    Filter.heldAxes = Potential.heldAxes();
    if (contacts() && Planes.pointCount() != state.positions.size())
    {
      Planes.reset(state.positions.size()); // the floor's plane for every point
    }
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
      if (contacts())
      {
        capture(Trial, TrialMotion); // the points whose start lies behind their plane
      }
      const double energy = Potential.evaluate(Trial, TrialGradient);
      if (energy < bestEnergy)
      {
        bestEnergy = energy;
        std::swap(X, Trial);
        std::swap(Filter.motion, TrialMotion);
      }
      if (!contacts())
      {
        break; // without contact the prediction is always the better start
      }
    }
    Stuck.resize(X.size(), 0);
    for (std::size_t i = 0; i < X.size(); ++i)
    {
      if (Stuck[i] && (!contacts() || !Planes.has(i)))
      {
        Stuck[i] = 0; // its surface is no longer near (a moving obstacle left it)
      }
      if (Stuck[i])
      {
        // Where static friction holds it: on its surface, moved with it.
        const Vec3& surfaceVelocity = Planes.of(i).velocity;
        X[i] = surfaceVelocity.isZero() ? state.positions[i] : Vec3(state.positions[i] + h * surfaceVelocity);
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
    if (contacts())
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

}

bool ImplicitStepSolver::carryBodyContactLoads()
{
  // A point held on another body's face is pushed by it with the normal part of Phi's gradient
  // at the solution (a stuck one with all of it); that body's face takes the opposite force,
  // spread over its corners by the point's barycentric weights.
  bool any = false;
  for (std::size_t i = 0; i < X.size(); ++i)
  {
    const bool held = Filter.motion[i] == PointMotion::OnPlane || Stuck[i];
    if (!held || !Planes.has(i) || !Planes.of(i).onBody())
    {
      continue;
    }
    const ContactPlane& plane = Planes.of(i);
    const Vec3 push = Stuck[i] ? Gradient[i] : Vec3(std::max(0.0, Gradient[i].dot(plane.normal)) * plane.normal);
    if (push.isZero())
    {
      continue;
    }
    if (!any)
    {
      ContactLoads.assign(X.size(), Vec3::Zero()); // kept between steps: no allocation once sized
      any = true;
    }
    for (int k = 0; k < 3; ++k)
    {
      ContactLoads[static_cast<std::size_t>(plane.corners[static_cast<std::size_t>(k)])] -= plane.weights(k) * push;
    }
  }
  if (any)
  {
    Potential.setContactLoads(&ContactLoads);
  }
  return any;
}

void ImplicitStepSolver::solveAgain(double h, const DynamicState& state, StepPlan& plan,
  const DirectionRule& rule, ImplicitConvergence& c)
{
  // The step's report covers every solve: their iterations, and one residual history with a
  // row per iteration (a later solve's starting residual is left out).
  const int earlierIterations = c.iterations;
  std::vector<double> history = std::move(c.residualHistory);
  solve(h, state, plan, rule, c);
  c.iterations += earlierIterations;
  history.insert(history.end(), c.residualHistory.begin() + 1, c.residualHistory.end());
  c.residualHistory = std::move(history);
}

void ImplicitStepSolver::step(double h, DynamicState& state, StepPlan& plan,
  const DirectionRule& rule, ImplicitConvergence& c)
{
  solve(h, state, plan, rule, c);
  // Bodies against bodies: each point is held on the other body's face where that body's
  // prediction puts it, which stops the point but leaves the other body unloaded in this
  // solve; projected apart after the step, a body landing on another crushes the tets between
  // them and the floor. So the holding pushes are carried to the faces they push on and the
  // step solved again with them as loads and with the planes moved to where the faces went;
  // kBodyContactPasses times (friction's solve below keeps the last loads).
  bool carried = false;
  for (int pass = 0; pass < kBodyContactPasses && contacts() && carryBodyContactLoads(); ++pass)
  {
    carried = true;
    Planes.followBodies(X);
    solveAgain(h, state, plan, rule, c);
  }
  // The contact response. Friction moves a point by h times its velocity change, which the
  // rest of the body did not answer; where that is more than a small part of its elements
  // (kFrictionShiftFraction of their size), a sticking point is held where it began (on its
  // surface) and the step solved again with it held, once, and a sliding point keeps the
  // solve's position. Moving them anyway would shift a landing body's bottom layer by its
  // whole slip in one step and crush the elements above it: a TetGen torus dropped onto a
  // 20-degree ramp at 1/20 s steps had 147 of its 3,949 tets inverted at once (47 on a level
  // floor), 6 with this rule (5), none frictionless.
  EndVelocity.resize(X.size());
  const auto respond = [&] {
    return parallelReduce(
      X.size(), 4096, std::size_t{ 0 },
      [&](std::size_t i) -> std::size_t {
        if (Filter.motion[i] == PointMotion::Fixed && !Stuck[i])
        {
          return 0; // pinned
        }
        bool holdAndSolveAgain = false;
        EndVelocity[i] = endVelocity(i, h, state.positions, holdAndSolveAgain);
        return holdAndSolveAgain ? 1 : 0;
      },
      sum);
  };
  if (respond() > 0)
  {
    solveAgain(h, state, plan, rule, c);
    respond();
  }
  if (carried)
  {
    Potential.setContactLoads(nullptr);
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
    state.velocities[i] = EndVelocity[i];
    state.positions[i] = X[i];
  });
}

Vec3 ImplicitStepSolver::endVelocity(
  std::size_t i, double h, const std::vector<Vec3>& start, bool& holdAndSolveAgain)
{
  if (Stuck[i])
  {
    // Held on its surface through the solve (release() frees it during the solve once the
    // force it takes leaves the friction cone; this is the final check).
    Stuck[i] = withinFrictionCone(i, Gradient[i]) ? 1 : 0;
    return Planes.of(i).velocity;
  }
  const Vec3 v = (X[i] - start[i]) / h;
  if (Filter.motion[i] != PointMotion::OnPlane)
  {
    return v;
  }
  const ContactPlane& plane = Planes.of(i);
  const Vec3& n = plane.normal;
  // Inelastic contact: a point held on its plane keeps no speed into it (relative to it).
  Vec3 relative = v - plane.velocity;
  relative -= std::min(0.0, relative.dot(n)) * n;
  // Coulomb friction on its slip (the plane inside the solve only holds points on it): the
  // plane's push over the step is the normal part of the potential's gradient at the solution
  // (the force the filter keeps the point from following), as a speed h F_n / m. The slip of
  // the step changes with the velocity, where that moves the point by a small part of its
  // elements (step() says why and what happens otherwise); a point that sticks stays on its
  // surface where the step began and is held there through the next solves (Stuck) rather
  // than put back after each, which would strain a stiff body anew every step.
  const double push = h * std::max(0.0, Gradient[i].dot(n)) * Potential.inverseMass(i);
  bool sticks = false;
  const Vec3 change = coulombFrictionChange(relative - relative.dot(n) * n, push, Friction, sticks);
  const double allowed = kFrictionShiftFraction * Planes.elementSize(i);
  if (allowed == 0.0 || h * change.norm() <= allowed)
  {
    X[i] += h * change;
  }
  else
  {
    holdAndSolveAgain = sticks;
  }
  Stuck[i] = sticks ? 1 : 0;
  // (A static surface's velocity is not added: 0 + -0 would turn the sign of a zero, and the
  // floor's results are kept to the bit.)
  return plane.velocity.isZero() ? Vec3(relative + change) : Vec3(plane.velocity + relative + change);
}

} // namespace softbody
