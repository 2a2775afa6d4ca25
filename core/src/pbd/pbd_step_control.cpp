// XPBD's error-controlled steps: the controller of common/error_control.h over PbdSimulation's
// steps. Each controlled step runs the user's substeps and iterations, so the estimate measures
// the error of the step the user would have fixed (time discretisation and what the iterations
// leave unconverged alike); a residual tolerance keeps the latter small.
#include "softbody/pbd/pbd_simulation.h"

#include <limits>

namespace softbody
{

void PbdSimulation::markPointsInContact(std::vector<char>& mask) const
{
  markContactPoints(Contacts, mask);
}

AdvanceStatus PbdSimulation::advanceWithErrorControl(double endTime, const ProgressCallback& progress)
{
  // XPBD's prediction and velocity update are those of symplectic Euler (or position Verlet,
  // the same first-order scheme in positions): order 1. The user's TimeStep bounds the steps.
  const ErrorControl control{ Settings.errorTolerance, 1,
    Settings.timeStep > 0.0 ? Settings.timeStep : std::numeric_limits<double>::infinity() };
  const bool linksChange = !State.linkRestLengths.empty();
  const auto takeStep = [&](double h) {
    if (linksChange)
    {
      // The controller puts the state back after a try; plastic rest lengths and broken links
      // go back with it.
      Links.rest = State.linkRestLengths;
      Links.broken = State.linkBroken;
      markBrokenTets();
    }
    // The frame's convergence is that of the step that ends on it (the halves' second).
    stepOnce(h, Settings.reportConvergence && State.time + h >= endTime * (1.0 - 1e-12));
    if (linksChange)
    {
      State.linkRestLengths = Links.rest;
      State.linkBroken = Links.broken;
      LinkStateStale = false;
    }
  };
  return softbody::advanceWithErrorControl(State, control, endTime, progress, takeStep,
    [&] { checkDivergence(); }, [&](std::vector<char>& mask) { markPointsInContact(mask); }, StepReport);
}

} // namespace softbody
