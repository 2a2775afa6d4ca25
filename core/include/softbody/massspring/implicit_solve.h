// The per-step minimization both implicit integrators share: minimize the incremental
// potential (incremental_potential.h) from the explicit prediction, along the descent
// directions the integrator supplies (Newton + PCG, or Projective Dynamics' prefactored solve),
// with a backtracking line search on Phi, until the residual acceleration is below the
// tolerance. The floor is an inequality handled inside the solve by an active set updated at
// every iteration (a primal active-set method): the line search starts from the longest step
// at which no free point crosses the floor (the ratio test), points that reach it are held on
// it and from then on slide along it (the motion filter), and a held point the floor would
// have to pull down (Phi's gradient pointing into the floor) is released. So the floor holds
// exactly at every iterate and the rest of the body answers it in the same step, instead of
// being crushed by a projection afterwards. Contact is inelastic, with Coulomb friction: a point
// static friction holds is fixed through the next step's solve (Stuck), and a point held on the
// floor leaves the step with the floor's contact response (endVelocity).
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

private:
  /// One descent iteration with its line search; false when it cannot make progress.
  bool iterate(StepPlan& plan, const DirectionRule& direction, ImplicitConvergence& c);
  void evaluateAtX();
  void filterGradient();
  /// The residual acceleration of `gradient` filtered by `motion`.
  double filteredResidual(const std::vector<Vec3>& gradient, const std::vector<PointMotion>& motion);
  /// Puts the free points of `x` that lie below the floor on it, held (OnPlane) in `motion`.
  std::size_t capture(std::vector<Vec3>& x, std::vector<PointMotion>& motion) const;
  /// Releases held points the floor would have to pull down, and stuck points whose force has
  /// left the friction cone.
  std::size_t release();
  /// Whether the floor can give a stuck point `force` (the potential's gradient there): a push,
  /// with a tangential part of at most staticFriction times it.
  bool withinFrictionCone(const Vec3& force) const;
  /// Holds free points on (or all but on) the floor that the search direction drives into it.
  std::size_t holdPointsOnTheFloorPath();
  /// The longest step length (<= 1) along the direction before a free point crosses the floor.
  double floorReach() const;
  /// After the solve: point i's velocity from its motion over the step (0 for a stuck point),
  /// with the floor's contact response (inelastic, Coulomb friction) for a point held on it.
  Vec3 endVelocity(std::size_t i, double h, const std::vector<Vec3>& start);

  IncrementalPotential& Potential;
  ImplicitSettings Settings;
  LineSearch Search;
  double GravityNorm;
  bool Floor;
  Vec3 FloorOrigin;
  CollisionSettings Friction; ///< the floor's static and dynamic friction
  /// Points that static friction holds where they are on the floor: fixed through the next
  /// step's solve, then kept while the force that took stays within the friction cone.
  std::vector<char> Stuck;
  MotionFilter Filter;
  std::vector<PointMotion> TrialMotion;
  bool Restart = true;
  double Reference = 1.0, Goal = 0.0, Energy = 0.0, Residual = 0.0, StartResidual = 1.0;
  std::vector<Vec3> X, Trial, Gradient, TrialGradient, Filtered, Direction, Scratch;
};

} // namespace softbody
