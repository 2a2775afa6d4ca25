/**
 * @class   vtkSoftBodyFrameRunner
 * @brief   The Soft Body filter's run-time state and its time protocol over the frame cache.
 *
 * Kept between requests: the simulation and the device it runs on, its frame cache, the
 * render surface's binding, the MPI distribution, the obstacles over time, and the key the
 * simulation was built from (input identity and modification time, core settings, Obstacles
 * connections, the Conditions' values over time). Simulate() brings the simulation to a requested time: it rebuilds only when
 * the key changed (and builds before it replaces, so a refused value keeps the cache), resumes
 * from the latest cached frame at or before the time, and caches every grid frame it passes.
 * What the filter does for it (warnings, errors, progress, abort) comes in as Hooks, so the
 * protocol holds no pipeline object.
 */
#ifndef vtkSoftBodyFrameRunner_h
#define vtkSoftBodyFrameRunner_h

#include "vtkSoftBodyDistribution.h"
#include "vtkSoftBodyFrameCache.h"
#include "vtkSoftBodyFrameTimings.h"
#include "vtkSoftBodyObstacleTimeline.h"
#include "vtkSoftBodyParameters.h"
#include "vtkSoftBodySettings.h"
#include "vtkSoftBodySimulationFactory.h"
#include "vtkSoftBodySkin.h"

#include "vtkType.h"

#include <functional>
#include <string>
#include <vector>

class vtkDataObject;
class vtkUnstructuredGrid;

/// How far a request got (declared opaquely in vtkSoftBodyFilter.h).
enum class vtkSoftBodyRunResult : int
{
  Done,
  Aborted,
  NeedsObstacles, ///< a moving obstacle is needed at a time not fetched yet
  Failed          ///< reported through Hooks::Error
};

class vtkSoftBodyFrameRunner
{
public:
  using Result = vtkSoftBodyRunResult;

  /// What the filter does for the protocol.
  struct Hooks
  {
    std::function<void(const std::string&)> Warn;
    std::function<void(const std::string&)> Error;
    std::function<void(double)> Progress; ///< fraction of the request done, in [0, 1]
    std::function<bool()> Abort;          ///< true: stop (the filter's CheckAbort)
  };

  /// Prepares the simulation and brings it to time `t`; core's exceptions are reported here
  /// (Failed) and discard a simulation that threw. Steps run are added to `stepsTotal`.
  Result Simulate(vtkUnstructuredGrid* input, const vtkSoftBodyCoreSettings& settings,
    const std::vector<vtkSoftBodyObstacleConnection>& obstacles,
    std::vector<softbody::ObstacleSurface> deliveredNow, double t, const vtkSoftBodyParameters& p,
    const Hooks& hooks, unsigned long long& stepsTotal);

  /// Forgets the simulation, its cached frames and its key.
  void Discard();
  /// The core settings the simulation was built from (the floor where the run placed it).
  const vtkSoftBodyCoreSettings& BuiltSettings() const { return this->Settings; }

  /// The simulation and the device it runs on.
  vtkSoftBodyBuiltSimulation Built;
  /// The optional render surface's binding to the body (kept while both are unchanged).
  vtkSoftBodySkin Skin;
  vtkSoftBodyFrameCache Cache;
  /// What each simulated frame, and the set-up, cost (the Timings port).
  vtkSoftBodyFrameTimings Timings;
  /// Under MPI: this rank's whole bodies, gathered and dealt from the ranks' pieces.
  vtkSoftBodyDistribution Distribution;
  /// The Obstacles input the simulation was built with, and the moving ones over time.
  vtkSoftBodyObstacleTimeline Obstacles;

  /// When the conditions' values changed during the run (their widgets moved): the frame
  /// times from which each change applies (empty when they never changed).
  std::vector<double> ConditionChangeTimes(double frameInterval) const;
  /// The conditions' values from frame 0 and after each of those changes, in that order.
  std::vector<std::vector<softbody::Condition>> ConditionValuesOverTheRun() const;

  std::string RunWarning;     ///< the run to EndTime will take long (steps, time, remedies)
  /// The implicit steps will land the body on the floor faster than its elements can take
  /// (vtkSoftBodyImplicitReport::LandingWarning); said before the run, like RunWarning.
  std::string LandingWarning;
  bool InversionSaid = false; ///< inverted tets were warned of (once per simulation)

private:
  /// Builds the simulation (and empties the cache) unless the input and the core settings it
  /// was built from are unchanged. Builds before it replaces: when the new settings or input
  /// are refused (false, or core's InvalidInputError), the current simulation and its cached
  /// frames stay, so that correcting the value finds them again.
  bool Prepare(vtkUnstructuredGrid* input, const vtkSoftBodyCoreSettings& settings,
    const std::vector<vtkSoftBodyObstacleConnection>& obstacles, const vtkSoftBodyParameters& p,
    const Hooks& hooks, double t);
  /// When only the conditions' values changed (a widget moved during playback) and the
  /// simulation takes them in place: keeps the frames up to the one at or before `t`, records
  /// the change from there on, drops the frames after it; values already in force at that
  /// frame keep every frame. False: build anew.
  bool ChangeConditionsLive(vtkUnstructuredGrid* input, const vtkSoftBodyCoreSettings& settings,
    const std::vector<vtkSoftBodyObstacleConnection>& obstacles, const vtkSoftBodyParameters& p,
    double t);
  /// Gives the simulation the conditions in force from grid frame `frame` on.
  void ApplyConditionsOf(int frame);
  /// The entry of ConditionEpochs in force at grid frame `frame`: the latest change at or
  /// before it.
  std::size_t EpochAt(int frame) const;
  /// Brings the simulation to time `t` through the cache, or as far as the moving obstacles
  /// fetched so far allow (NeedsObstacles: the next pass fetches the missing time).
  Result AdvanceTo(
    double t, const vtkSoftBodyParameters& p, const Hooks& hooks, unsigned long long& stepsTotal);

  /// Grid frame the simulation's state is exactly at; -1 when between frames or unknown.
  int SimulationFrame = -1;
  // The key: which input (object and modification time) and which core settings the
  // simulation was built from (and the Obstacles' connections).
  const vtkDataObject* Input = nullptr; // identity only, never dereferenced
  vtkMTimeType InputMTime = 0;
  vtkSoftBodyCoreSettings Settings;
  std::string RunWarningSaid; ///< the last long-run warning printed, so it is said once
  std::string LandingWarningSaid; ///< the last landing warning printed
  /// The conditions' values over the run: from grid frame `first` on, `second` (the first
  /// entry from frame 0; one more per change made during playback).
  std::vector<std::pair<int, std::vector<softbody::Condition>>> ConditionEpochs;
  std::size_t AppliedEpoch = 0; ///< the entry the simulation holds now
};

#endif
