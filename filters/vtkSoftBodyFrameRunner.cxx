#include "vtkSoftBodyFrameRunner.h"

#include "vtkSoftBodyArrays.h"
#include "vtkSoftBodyImplicitReport.h"

#include "vtkLogger.h"
#include "vtkUnstructuredGrid.h"

#include "softbody/common/errors.h"

#include <algorithm>
#include <chrono>
#include <sstream>
#include <stdexcept>

//------------------------------------------------------------------------------
void vtkSoftBodyFrameRunner::Discard()
{
  this->Built = vtkSoftBodyBuiltSimulation();
  this->InversionSaid = false;
  this->Cache.Clear();
  this->Timings.Reset(0.0);
  this->SimulationFrame = -1;
  this->Input = nullptr;
  this->Obstacles.Reset({});
  this->ConditionEpochs.clear();
  this->AppliedEpoch = 0;
}

//------------------------------------------------------------------------------
vtkSoftBodyFrameRunner::Result vtkSoftBodyFrameRunner::Simulate(vtkUnstructuredGrid* input,
  const vtkSoftBodyCoreSettings& settings,
  const std::vector<vtkSoftBodyObstacleConnection>& obstacles,
  std::vector<softbody::ObstacleSurface> deliveredNow, double t, const vtkSoftBodyParameters& p,
  const Hooks& hooks, unsigned long long& stepsTotal)
{
  // Core reports unusable input and divergence by exceptions; they must not cross into the
  // pipeline, and a simulation that threw is not trusted again. A refusal while building a
  // new simulation (core validates the settings then) leaves the current one and its cache
  // untouched (PrepareSimulation builds before it replaces): they are kept.
  vtkSoftBodyFrameRunner& internals = *this;
  bool prepared = false;
  try
  {
    if (!this->Prepare(input, settings, obstacles, p, hooks, t))
    {
      return Result::Failed;
    }
    prepared = true;
    internals.Obstacles.Record(std::move(deliveredNow));
    // Said before a long run starts (and again only if EndTime or the simulation changes it).
    internals.RunWarning = internals.Built.Simulation->longRunWarning(p.EndTime);
    if (!internals.RunWarning.empty() && internals.RunWarning != internals.RunWarningSaid)
    {
      hooks.Warn(internals.RunWarning);
      internals.RunWarningSaid = internals.RunWarning;
    }
    // An implicit step is TimeStep, or the whole frame at TimeStep = 0.
    internals.LandingWarning = vtkSoftBodyImplicitReport::LandingWarning(
      *internals.Built.Simulation, p.TimeStep > 0.0 ? p.TimeStep : p.FrameInterval);
    if (!internals.LandingWarning.empty() && internals.LandingWarning != internals.LandingWarningSaid)
    {
      hooks.Warn(internals.LandingWarning);
      internals.LandingWarningSaid = internals.LandingWarning;
    }
    return this->AdvanceTo(t, p, hooks, stepsTotal);
  }
  catch (const softbody::InvalidInputError& e)
  {
    hooks.Error(e.what());
    if (prepared)
    {
      internals.Discard();
    }
  }
  catch (const softbody::SimulationDivergedError& e)
  {
    // Core's message already names the time and what to change.
    hooks.Error(e.what());
    internals.Discard();
  }
  catch (const std::exception& e)
  {
    hooks.Error(std::string("The simulation failed: ") + e.what());
    if (prepared)
    {
      internals.Discard();
    }
  }
  return Result::Failed;
}

//------------------------------------------------------------------------------
bool vtkSoftBodyFrameRunner::Prepare(vtkUnstructuredGrid* input,
  const vtkSoftBodyCoreSettings& settings,
  const std::vector<vtkSoftBodyObstacleConnection>& obstacles, const vtkSoftBodyParameters& p,
  const Hooks& hooks, double t)
{
  vtkSoftBodyFrameRunner& internals = *this;
  internals.Cache.SetMemoryLimit(static_cast<std::size_t>(p.CacheMemoryLimit) << 20);

  if (internals.ChangeConditionsLive(input, settings, obstacles, p, t))
  {
    return true;
  }

  // The key is what the simulation is built from; EndTime and CacheMemoryLimit are not part
  // of it, nor is any property the method ignores, so changing those keeps the cache.
  if (internals.Built.Simulation && internals.Input == input &&
    internals.InputMTime == vtkSoftBodyArrays::ContentMTime(input) && internals.Settings == settings &&
    internals.Obstacles.GetConnections() == obstacles)
  {
    return true;
  }

  // Build the new simulation aside and discard the current one only once that succeeded:
  // core validates the settings (and the input) while it builds, so a value it refuses
  // throws here, and the cached frames must still be there when the value is put back.
  const auto setupStarted = std::chrono::steady_clock::now();
  vtkSoftBodyBuiltSimulation built;
  std::string error;
  if (!vtkSoftBodySimulationFactory::Build(input, settings, !obstacles.empty(),
        hooks.Warn, built, error))
  {
    hooks.Error(error);
    return false;
  }
  // Static obstacles are set once (they are not part of the state the cache restores);
  // moving ones before every frame (AdvanceTo). Throws InvalidInputError for a method that
  // cannot collide with obstacles or a bad surface: the current simulation stays.
  vtkSoftBodyObstacleTimeline::SetStaticObstacles(obstacles, *built.Simulation);
  internals.Discard();
  internals.Timings.Reset(
    std::chrono::duration<double>(std::chrono::steady_clock::now() - setupStarted).count());
  internals.Built = std::move(built);
  internals.Obstacles.Reset(obstacles);
  internals.Cache.Insert(0, internals.Built.Simulation->state());
  internals.SimulationFrame = 0;
  internals.Input = input;
  internals.InputMTime = vtkSoftBodyArrays::ContentMTime(input);
  internals.Settings = settings;
  internals.ConditionEpochs.assign(1, { 0, settings.Conditions });
  internals.AppliedEpoch = 0;

  // Said once per simulation, not on every frame; the Warnings field data repeats them.
  const std::vector<std::string>& warnings = internals.Built.Simulation->warnings();
  if (!warnings.empty())
  {
    std::ostringstream msg;
    for (const std::string& warning : warnings)
    {
      msg << "\n  " << warning;
    }
    hooks.Warn("Soft body set up with warnings:" + msg.str());
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkSoftBodyFrameRunner::ChangeConditionsLive(vtkUnstructuredGrid* input,
  const vtkSoftBodyCoreSettings& settings,
  const std::vector<vtkSoftBodyObstacleConnection>& obstacles, const vtkSoftBodyParameters& p,
  double t)
{
  // Only the conditions' values changed (the same body, settings and sets): the frames up to
  // the one shown stay, the change applies from there on, and the frames after it are
  // simulated anew. A change of anything else builds the simulation again.
  vtkSoftBodyCoreSettings same = this->Settings;
  same.Conditions = settings.Conditions;
  if (!this->Built.Simulation || this->Input != input || this->InputMTime != vtkSoftBodyArrays::ContentMTime(input) ||
    !(same == settings) || this->Settings.Conditions == settings.Conditions ||
    this->Obstacles.GetConnections() != obstacles || this->ConditionEpochs.empty())
  {
    return false;
  }
  const vtkSoftBodyFrameGrid grid{ p.FrameInterval, p.EndTime };
  bool onGrid = true;
  int frame = grid.FrameOf(t, onGrid);
  frame = (!onGrid && frame * p.FrameInterval > t) ? frame - 1 : frame;
  frame = std::max(frame, 0);
  // The values already in force at that frame (recorded keyframes set them again as the
  // animation is played again or scrubbed): nothing changes there, every frame stays.
  if (settings.Conditions == this->ConditionEpochs[this->EpochAt(frame)].second)
  {
    this->Settings = settings;
    return true;
  }
  // Try the new values on the simulation as it is (a refused value keeps everything).
  if (!this->Built.Simulation->setConditionValues(settings.Conditions))
  {
    return false; // a set, a kind or a held component changed: build anew
  }
  while (!this->ConditionEpochs.empty() && this->ConditionEpochs.back().first >= frame &&
    this->ConditionEpochs.size() > 1)
  {
    this->ConditionEpochs.pop_back();
  }
  if (this->ConditionEpochs.back().first >= frame)
  {
    this->ConditionEpochs.back().second = settings.Conditions; // a change at frame 0
  }
  else
  {
    this->ConditionEpochs.emplace_back(frame, settings.Conditions);
  }
  this->AppliedEpoch = this->ConditionEpochs.size() - 1;
  this->Cache.DropAfter(frame);
  this->Timings.DropAfter(frame);
  this->SimulationFrame = -1; // resume from the cached frame
  this->Settings = settings;
  return true;
}

//------------------------------------------------------------------------------
std::size_t vtkSoftBodyFrameRunner::EpochAt(int frame) const
{
  std::size_t epoch = 0;
  for (std::size_t e = 0; e < this->ConditionEpochs.size(); ++e)
  {
    if (this->ConditionEpochs[e].first <= frame)
    {
      epoch = e;
    }
  }
  return epoch;
}

//------------------------------------------------------------------------------
void vtkSoftBodyFrameRunner::ApplyConditionsOf(int frame)
{
  // The latest change at or before the frame the next step starts from.
  const std::size_t epoch = this->EpochAt(frame);
  if (epoch != this->AppliedEpoch && epoch < this->ConditionEpochs.size())
  {
    // Every entry has the sets the simulation was built with (ChangeConditionsLive checked).
    if (!this->Built.Simulation->setConditionValues(this->ConditionEpochs[epoch].second))
    {
      throw std::logic_error("a recorded condition change no longer fits the simulation");
    }
    this->AppliedEpoch = epoch;
  }
}

//------------------------------------------------------------------------------
std::vector<double> vtkSoftBodyFrameRunner::ConditionChangeTimes(double frameInterval) const
{
  std::vector<double> times;
  for (std::size_t e = 1; e < this->ConditionEpochs.size(); ++e)
  {
    times.push_back(this->ConditionEpochs[e].first * frameInterval);
  }
  return times;
}

//------------------------------------------------------------------------------
std::vector<std::vector<softbody::Condition>> vtkSoftBodyFrameRunner::ConditionValuesOverTheRun() const
{
  std::vector<std::vector<softbody::Condition>> values;
  for (const auto& epoch : this->ConditionEpochs)
  {
    values.push_back(epoch.second);
  }
  return values;
}

//------------------------------------------------------------------------------
vtkSoftBodyFrameRunner::Result vtkSoftBodyFrameRunner::AdvanceTo(
  double t, const vtkSoftBodyParameters& p, const Hooks& hooks, unsigned long long& stepsTotal)
{
  vtkSoftBodyFrameRunner& internals = *this;
  softbody::Simulation& simulation = *internals.Built.Simulation;
  const vtkSoftBodyFrameGrid grid{ p.FrameInterval, p.EndTime };
  bool onGrid = true;
  const int target = grid.FrameOf(t, onGrid);

  // Resume from the latest cached frame at or before the target, unless the simulation itself
  // is already at a frame that is at least as close (it may be one the cache evicted).
  int cached = -1;
  const softbody::DynamicState* snapshot = internals.Cache.FindLatestAtOrBefore(target, cached);
  const bool simulationIsCloser = internals.SimulationFrame >= 0 &&
    internals.SimulationFrame <= target && internals.SimulationFrame >= cached;
  if (!simulationIsCloser)
  {
    if (!snapshot)
    {
      // Frame 0 is never evicted, so this cannot happen; fail loudly rather than guess.
      throw std::logic_error("the frame cache lost frame 0");
    }
    simulation.restoreState(*snapshot);
    internals.SimulationFrame = cached;
  }

  // Progress runs over the frames still to simulate (plus the final partial interval).
  const int first = internals.SimulationFrame;
  const int framesToRun = target - first + (onGrid ? 0 : 1);
  if (framesToRun <= 0)
  {
    return Result::Done;
  }
  double lastReported = -1.0;
  int framesDone = 0;
  bool aborted = false;
  // Called by core during advance(); reports at most every 0.5% and checks abort there, since
  // CheckAbort walks the pipeline and core may call this every step.
  const softbody::ProgressCallback progress = [&](double fraction) {
    const double total = (framesDone + fraction) / framesToRun;
    if (total - lastReported < 0.005)
    {
      return true;
    }
    lastReported = total;
    hooks.Progress(total);
    aborted = hooks.Abort();
    return !aborted;
  };

  auto runTo = [&](double endTime) {
    const unsigned long long before = simulation.stepCount();
    const softbody::AdvanceStatus status = simulation.advance(endTime, progress);
    stepsTotal += simulation.stepCount() - before;
    return status == softbody::AdvanceStatus::Completed && !aborted;
  };

  // A run announced as long also says, in the log (visible in pvpython, where no progress bar
  // is), how far it got and how long the rest will take: at most one line every 10 s.
  const auto started = std::chrono::steady_clock::now();
  auto lastLog = started;
  auto logLongRunProgress = [&](int frame) {
    const auto now = std::chrono::steady_clock::now();
    if (internals.RunWarning.empty() || now - lastLog < std::chrono::seconds(10))
    {
      return;
    }
    lastLog = now;
    const double elapsed = std::chrono::duration<double>(now - started).count();
    const double left = elapsed / framesDone * (framesToRun - framesDone);
    vtkLogF(INFO, "Soft Body: frame %d of %d simulated (t = %g s) in %.0f s; about %.0f s to go.",
      frame, target, frame * p.FrameInterval, elapsed, left);
  };
  for (int k = first + 1; k <= target; ++k)
  {
    internals.ApplyConditionsOf(k - 1);
    if (!internals.Obstacles.SetForInterval(
          simulation, (k - 1) * p.FrameInterval, k * p.FrameInterval))
    {
      return Result::NeedsObstacles; // still exactly at frame k - 1
    }
    const std::vector<softbody::StageTiming> stagesBefore = simulation.stageTimings();
    const auto frameStarted = std::chrono::steady_clock::now();
    if (hooks.Abort() || !runTo(k * p.FrameInterval))
    {
      internals.SimulationFrame = -1; // stopped somewhere inside frame k
      return Result::Aborted;
    }
    internals.SimulationFrame = k;
    internals.Cache.Insert(k, simulation.state());
    internals.Timings.Record(k, k * p.FrameInterval, stagesBefore, simulation.stageTimings(),
      std::chrono::duration<double>(std::chrono::steady_clock::now() - frameStarted).count());
    ++framesDone;
    logLongRunProgress(k);
  }
  if (!onGrid)
  {
    // Off-grid times (only EndTime, or a time a script asks for) are not cached: the next
    // request resumes from the grid frame before them.
    internals.ApplyConditionsOf(target);
    if (!internals.Obstacles.SetForInterval(simulation, target * p.FrameInterval, t))
    {
      return Result::NeedsObstacles;
    }
    internals.SimulationFrame = -1;
    if (hooks.Abort() || !runTo(t))
    {
      return Result::Aborted;
    }
  }
  hooks.Progress(1.0);
  return Result::Done;
}
