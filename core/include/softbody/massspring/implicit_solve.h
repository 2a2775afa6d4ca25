// The per-step minimization both implicit integrators share: minimize the incremental
// potential (incremental_potential.h) from the explicit prediction, along the descent
// directions the integrator supplies (Newton + PCG, or Projective Dynamics' prefactored solve),
// with a backtracking line search on Phi, until the residual acceleration is below the
// tolerance. The floor and the obstacles are inequalities handled inside the solve, each point
// against its contact plane (contact_planes.h: the floor, or the obstacle face it is heading
// for), by an active set updated at every iteration (a primal active-set method): the line
// search starts from the longest step at which no free point crosses its plane (the ratio test,
// a continuous collision check along the search path), points that reach it are held on it and
// from then on slide along it (the motion filter), and a held point its plane would have to
// pull back (Phi's gradient pointing into it) is released. So contacts hold exactly at every
// iterate and the rest of the body answers them in the same step, instead of being crushed by
// a projection afterwards. Contact is inelastic, with Coulomb friction on the slip relative to
// the surface: a point static friction holds moves with its surface through the next step's
// solve (Stuck), and a point held on a plane leaves the step with the contact response
// (endVelocity).
#pragma once

#include "softbody/common/state.h"
#include "softbody/common/step_plan.h"
#include "softbody/massspring/implicit_convergence.h"
#include "softbody/massspring/incremental_potential.h"
#include "softbody/massspring/mass_spring_settings.h"
#include "softbody/massspring/motion_filter.h"

#include <functional>

namespace softbody
{

class ImplicitStepSolver
{
public:
  /// What a direction rule is given: the iterate, Phi's gradient there, the filter, whether
  /// this is the step's first iteration (history from earlier steps must be dropped; contact
  /// changes within a step keep it: the rule filters its direction), and the relative residual
  /// and goal (so a rule solves no more precisely than needed).
  struct Iterate
  {
    StepPlan& plan; ///< the rule times its own stages (Forces for assembly, LinearSolve)
    const std::vector<Vec3>& x;
    const std::vector<Vec3>& gradient;
    const MotionFilter& filter;
    bool restart;
    double relativeResidual; ///< residual over the step's starting residual
    double relativeGoal;     ///< the tolerance's goal over the step's starting residual
  };
  /// Fills `direction` with a descent direction of Phi, filtered by the filter. Returns the
  /// linear iterations it ran (0 if none).
  using DirectionRule = std::function<int(const Iterate& at, std::vector<Vec3>& direction)>;

  enum class LineSearch
  {
    Armijo,  ///< sufficient decrease (Newton's directions come with a model of Phi)
    Decrease ///< any decrease (Projective Dynamics)
  };

  ImplicitStepSolver(IncrementalPotential& potential, const SceneSettings& scene,
    LineSearch lineSearch);

  /// One step of h: positions and velocities of `state` (time and counters are the caller's).
  /// Element passes are timed as Stage::Forces, contact updates as Stage::Floor.
  void step(double h, DynamicState& state, StepPlan& plan, const DirectionRule& direction,
    ImplicitConvergence& convergence);

  /// The contact planes of the coming steps: the floor's alone unless the owner adds the
  /// obstacles' and other bodies' before each step (ContactPlanes::reset, addContacts).
  ContactPlanes& contactPlanes() { return Planes; }

private:
  /// Minimizes Phi over the step from `state` (fills X, Gradient; counts c.iterations, keeps
  /// c.residualHistory); the stuck points are held.
  void solve(double h, const DynamicState& state, StepPlan& plan, const DirectionRule& direction,
    ImplicitConvergence& c);
  /// One descent iteration with its line search; false when it cannot make progress.
  bool iterate(StepPlan& plan, const DirectionRule& direction, ImplicitConvergence& c);
  void evaluateAtX();
  void filterGradient();
  /// The residual acceleration of `gradient` filtered by `motion`.
  double filteredResidual(const std::vector<Vec3>& gradient, const std::vector<PointMotion>& motion);
  /// Whether some point has a contact plane.
  bool contacts() const { return !Planes.empty(); }
  /// Sets the potential's contact loads from the points held on other bodies' faces; false
  /// when there are none.
  bool carryBodyContactLoads();
  std::vector<Vec3> ContactLoads; ///< [N] per point, what carryBodyContactLoads set
  /// solve() once more, its iterations and residuals added to the step's report.
  void solveAgain(double h, const DynamicState& state, StepPlan& plan, const DirectionRule& direction,
    ImplicitConvergence& c);
  /// Puts the free points of `x` that lie behind their plane on it, held (OnPlane) in `motion`.
  std::size_t capture(std::vector<Vec3>& x, std::vector<PointMotion>& motion) const;
  /// Releases held points their plane would have to pull back, and stuck points whose force
  /// has left the friction cone.
  std::size_t release();
  /// Whether point i's plane can give it `force` (the potential's gradient there): a push, with
  /// a tangential part of at most staticFriction times it.
  bool withinFrictionCone(std::size_t i, const Vec3& force) const;
  /// Holds free points on (or all but on) their plane that the search direction drives into it.
  std::size_t holdPointsOnThePath();
  /// The longest step length (<= 1) along the direction before a free point crosses its plane.
  double contactReach() const;
  /// After the solve: point i's velocity from its motion over the step (its surface's for a
  /// stuck point), with the contact response (inelastic, Coulomb friction) for a point held on
  /// its plane.
  /// `holdAndSolveAgain`: it sticks, and moving it where it began would strain its elements.
  Vec3 endVelocity(std::size_t i, double h, const std::vector<Vec3>& start, bool& holdAndSolveAgain);

  IncrementalPotential& Potential;
  ImplicitSettings Settings;
  LineSearch Search;
  double GravityNorm;
  ContactPlanes Planes;
  CollisionSettings Friction; ///< the contacts' static and dynamic friction
  /// Points that static friction holds on their plane: moved with its surface through the next
  /// step's solve, then kept while the force that took stays within the friction cone.
  std::vector<char> Stuck;
  MotionFilter Filter;
  std::vector<PointMotion> TrialMotion;
  bool Restart = true;
  double Reference = 1.0, Goal = 0.0, Energy = 0.0, Residual = 0.0, StartResidual = 1.0;
  std::vector<Vec3> EndVelocity; ///< per point, after the contact response
  std::vector<Vec3> X, Trial, Gradient, TrialGradient, Filtered, Direction, Scratch;
};

} // namespace softbody
