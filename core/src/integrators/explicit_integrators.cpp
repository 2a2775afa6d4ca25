#include "softbody/integrators/explicit_integrators.h"

#include <stdexcept>

#include "softbody/common/parallel.h"

namespace softbody
{
namespace
{

constexpr std::size_t kGrain = 4096;

/// Runs body(i) for every point, in parallel. Each i is written by exactly one task.
template <typename Function>
void forEachPoint(std::size_t count, const Function& body)
{
  parallelFor(count, kGrain, body);
}

void explicitEuler(double h, const AccelerationEvaluator& evaluator, DynamicState& s,
  IntegratorScratch& w)
{
  evaluator.evaluate(s.time, s.positions, s.velocities, w.acceleration);
  forEachPoint(s.positions.size(), [&](std::size_t i) {
    s.positions[i] += h * s.velocities[i];
    s.velocities[i] += h * w.acceleration[i];
  });
}

/// RK2 midpoint: evaluate at (x + h/2 v, v + h/2 a), then take the full step with those rates.
void midpoint(double h, const AccelerationEvaluator& evaluator, DynamicState& s,
  IntegratorScratch& w)
{
  evaluator.evaluate(s.time, s.positions, s.velocities, w.acceleration);
  w.midPositions.resize(s.positions.size());
  w.midVelocities.resize(s.positions.size());
  forEachPoint(s.positions.size(), [&](std::size_t i) {
    w.midPositions[i] = s.positions[i] + 0.5 * h * s.velocities[i];
    w.midVelocities[i] = s.velocities[i] + 0.5 * h * w.acceleration[i];
  });
  evaluator.evaluate(s.time + 0.5 * h, w.midPositions, w.midVelocities, w.acceleration);
  forEachPoint(s.positions.size(), [&](std::size_t i) {
    s.positions[i] += h * w.midVelocities[i];
    s.velocities[i] += h * w.acceleration[i];
  });
}

/// Kick (velocity by kick * a) then drift (position by h * new velocity). Euler-Cromer kicks by
/// h; leapfrog Verlet by the mean of the previous and current step (h/2 on the first step).
void kickDrift(double h, double kick, const AccelerationEvaluator& evaluator, DynamicState& s,
  IntegratorScratch& w)
{
  evaluator.evaluate(s.time, s.positions, s.velocities, w.acceleration);
  forEachPoint(s.positions.size(), [&](std::size_t i) {
    s.velocities[i] += kick * w.acceleration[i];
    s.positions[i] += h * s.velocities[i];
  });
}

} // namespace

void integrateStep(Integrator integrator, double h, const AccelerationEvaluator& evaluator,
  DynamicState& state, IntegratorScratch& scratch)
{
  switch (integrator)
  {
    case Integrator::Euler:
      explicitEuler(h, evaluator, state, scratch);
      break;
    case Integrator::Midpoint:
      midpoint(h, evaluator, state, scratch);
      break;
    case Integrator::Verlet:
      kickDrift(h, 0.5 * (state.previousStep + h), evaluator, state, scratch);
      if (!state.previousAccelerations.empty()) // kept for the error estimate (local_error.h)
      {
        state.previousAccelerations = scratch.acceleration;
      }
      break;
    case Integrator::EulerCromer:
      kickDrift(h, h, evaluator, state, scratch);
      break;
    case Integrator::ImplicitEuler:
    case Integrator::ProjectiveDynamics:
    case Integrator::Static:
    case Integrator::Bdf2:
    case Integrator::VertexBlockDescent:
      throw std::logic_error("integrateStep: implicit integrators have their own steppers");
  }
  state.time += h;
  state.previousStep = h;
  ++state.stepCount;
}

} // namespace softbody
