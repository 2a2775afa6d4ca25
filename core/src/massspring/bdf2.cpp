#include "softbody/massspring/bdf2.h"

#include "softbody/common/parallel.h"

#include <cmath>

namespace softbody
{

Bdf2Stepper::Bdf2Stepper(const Topology& topology, const BodyElements& elements,
  const PointMasses& masses, const std::vector<Vec3>& restPositions, const SceneSettings& scene)
  : BackwardEuler(topology, elements, masses, restPositions, scene)
{
}

double bdf2HalvesErrorFactor(double h, double previousStep)
{
  const double whole = previousStep > 0.0 ? h / previousStep : 0.0;
  const double firstHalf = 0.5 * whole;
  if (!(whole > 0.0) || whole > kBdf2MaxStepRatio)
  {
    return 1.0 / 3.0; // the whole step is backward Euler's: Richardson's first-order factor
  }
  // whole: C(w) h^3; halves: (C(w / 2) + C(1)) (h / 2)^3 (the first half's error carried
  // through the second unchanged, to leading order).
  const double halves = (Bdf2Coefficients::errorConstant(firstHalf) + Bdf2Coefficients::errorConstant(1.0)) / 8.0;
  return halves / std::abs(Bdf2Coefficients::errorConstant(whole) - halves);
}

void Bdf2Stepper::step(double h, DynamicState& state, StepPlan& plan)
{
  const std::size_t n = state.positions.size();
  const IncrementalPotential& potential = BackwardEuler.potential();
  if (!isBdf2Step(state, h))
  {
    state.previousPositions = state.positions;
    state.previousVelocities = state.velocities;
    ExtrapolatedStart = state.positions;
    BackwardEuler.step(h, state, plan);
    restartWhereTheResponseActed(h, h, state);
    return;
  }
  const Bdf2Coefficients k = Bdf2Coefficients::forRatio(h / state.previousStep);
  Extrapolated.positions.resize(n);
  Extrapolated.velocities.resize(n);
  parallelFor(n, 4096, [&](std::size_t i) {
    // Points without mass do not move in the solve: they keep their positions exactly (a - b
    // is 1 only up to rounding).
    Extrapolated.positions[i] = !potential.active()[i]
      ? state.positions[i]
      : Vec3(k.a * state.positions[i] - k.b * state.previousPositions[i]);
    Extrapolated.velocities[i] = k.a * state.velocities[i] - k.b * state.previousVelocities[i];
  });
  const double solveStep = k.beta * h;
  Extrapolated.time = state.time + h - solveStep; // the solve ends where the step does
  ExtrapolatedStart = Extrapolated.positions;
  BackwardEuler.step(solveStep, Extrapolated, plan);
  std::swap(state.previousPositions, state.positions);
  std::swap(state.previousVelocities, state.velocities);
  state.positions = Extrapolated.positions;
  state.velocities = Extrapolated.velocities;
  parallelFor(n, 4096, [&](std::size_t i) {
    if (!potential.active()[i])
    {
      state.positions[i] = state.previousPositions[i];
      state.velocities[i] = state.previousVelocities[i];
    }
  });
  restartWhereTheResponseActed(h, solveStep, state);
}

void Bdf2Stepper::restartWhereTheResponseActed(double h, double solveStep, DynamicState& state)
{
  const IncrementalPotential& potential = BackwardEuler.potential();
  parallelFor(state.positions.size(), 4096, [&](std::size_t i) {
    if (!potential.active()[i])
    {
      return;
    }
    // The solve's velocity of a free point is (x+ - its start) / its step, to the bit; one
    // that differs was changed by the contact response.
    const Vec3 solved = (state.positions[i] - ExtrapolatedStart[i]) / solveStep;
    if (solved != state.velocities[i])
    {
      state.previousPositions[i] = state.positions[i] - h * state.velocities[i];
      state.previousVelocities[i] = state.velocities[i];
    }
  });
}

} // namespace softbody
