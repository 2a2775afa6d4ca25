// The contract every soft-body stepper fulfils (CPU mass-spring, GPU mass-spring, PBD/XPBD):
// the VTK filter, its frame cache and the benchmarks talk to this interface only.
#pragma once

#include "softbody/collision/obstacle.h"
#include "softbody/common/geometry.h"
#include "softbody/common/state.h"
#include "softbody/common/step_plan.h"
#include "softbody/common/tet_stress_field.h"
#include "softbody/scene/boundary_conditions.h"

#include <functional>
#include <string>
#include <vector>

namespace softbody
{

struct StepControlReport; // common/error_control.h

/// Called during advance() with the fraction done; return false to abort.
using ProgressCallback = std::function<bool(double fraction)>;

enum class AdvanceStatus
{
  Completed,
  Aborted
};

class Simulation
{
public:
  virtual ~Simulation() = default;

  /// Advances to `endTime` (>= time()) in equal steps no larger than stepSize(): the interval
  /// is split into ceil(interval / stepSize()) steps, so a run that stops at frame times
  /// produces exactly the same states as one that does not stop. Throws
  /// SimulationDivergedError if the state turns non-finite or explodes.
  virtual AdvanceStatus advance(double endTime, const ProgressCallback& progress = {}) = 0;

  /// The whole state needed to resume (a frame-cache snapshot).
  virtual const DynamicState& state() const = 0;
  /// Resumes from a snapshot taken from this simulation (same body and settings).
  virtual void restoreState(const DynamicState& snapshot) = 0;

  double time() const { return state().time; }
  unsigned long long stepCount() const { return state().stepCount; }
  const std::vector<Vec3>& positions() const { return state().positions; }
  const std::vector<Vec3>& velocities() const { return state().velocities; }

  virtual const std::vector<Vec3>& restPositions() const = 0;
  virtual const std::vector<double>& inverseMasses() const = 0;
  virtual double totalMass() const = 0;

  /// Current over rest volume of each tet, in input cell order; empty for bodies without tets.
  virtual std::vector<double> tetVolumeRatios() const = 0;
  /// Strain, stress and energy density per tet, in the order tetVolumeRatios() has; empty
  /// where the body has no continuum model.
  virtual TetStressField stressField() const { return {}; }
  /// Reactions at held points (input point order) and each condition's total force and
  /// moment at the current state; empty where the body has no conditions.
  virtual ConditionReadout conditionReadout() const { return {}; }
  /// New values for the body's conditions from the current state on (a condition's widget
  /// moved during playback): the same conditions with the same sets, points in input order.
  /// Returns false where the stepper cannot change them in place (the caller rebuilds);
  /// throws InvalidInputError for a bad value.
  virtual bool setConditionValues(const std::vector<Condition>& /*conditions*/) { return false; }
  /// Elastic energy of the current state [J]; NaN where the stepper does not say.
  virtual double elasticEnergy() const;
  /// Kinetic energy sum m v^2 / 2 of the free points [J].
  double kineticEnergy() const;

  /// Whether setObstacles() is supported (the GPU stepper does not: the filter falls back to
  /// the CPU with a warning).
  virtual bool supportsObstacles() const { return false; }
  /// Replaces the obstacle surfaces the body collides with; their `vertices` hold at
  /// `endTime`, the end of the coming advance() (obstacle.h). Throws InvalidInputError for bad
  /// surfaces, or when !supportsObstacles().
  virtual void setObstacles(std::vector<ObstacleSurface> obstacles, double endTime);

  /// Error-controlled steps (Scene::stepControl): what the controller did in the last
  /// advance(); null with fixed steps.
  virtual const StepControlReport* stepControlReport() const { return nullptr; }

  virtual double stepSize() const = 0;            ///< [s]
  virtual double estimatedStableStep() const = 0; ///< [s]; 0 if none is stable or not relevant

  /// Said before a run of `duration` simulated seconds that would take long (step count, wall
  /// time estimate, remedies); empty when it will not.
  virtual std::string longRunWarning(double /*duration*/) const { return {}; }

  /// Everything worth telling the user once (clamped parameters, re-oriented tets, ...).
  virtual const std::vector<std::string>& warnings() const = 0;
  /// The stages this scene runs per step, in order (only those it needs), each with the wall
  /// time spent in it so far. Decided once by the method's planner.
  virtual const StepPlan& stepPlan() const = 0;
  std::vector<Stage> plan() const { return stepPlan().stages(); }
  std::vector<StageTiming> stageTimings() const { return stepPlan().timings(); }
};

} // namespace softbody
