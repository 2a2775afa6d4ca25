// The four integrators against analytic solutions: free fall and the harmonic oscillator.
#include "softbody/massspring/explicit_integrators.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace softbody;

namespace
{

const Integrator kAll[] = { Integrator::Euler, Integrator::Midpoint, Integrator::Verlet,
  Integrator::EulerCromer };

/// x'' = -omega^2 x for every point (one independent oscillator per point).
class Oscillator final : public AccelerationEvaluator
{
public:
  explicit Oscillator(double omega)
    : Omega2(omega * omega)
  {
  }
  void evaluate(const std::vector<Vec3>& x, const std::vector<Vec3>&, std::vector<Vec3>& a) const override
  {
    a.resize(x.size());
    for (std::size_t i = 0; i < x.size(); ++i)
    {
      a[i] = -Omega2 * x[i];
    }
  }

private:
  double Omega2;
};

/// |x(T) - cos(omega T)| after integrating from x = 1, v = 0 with step h.
double oscillatorError(Integrator integrator, double h, double endTime)
{
  const double omega = 2.0 * M_PI; // period 1 s
  DynamicState state;
  state.positions = { Vec3(1, 0, 0) };
  state.velocities = { Vec3::Zero() };
  IntegratorScratch scratch;
  const auto steps = static_cast<int>(std::lround(endTime / h));
  for (int s = 0; s < steps; ++s)
  {
    integrateStep(integrator, h, Oscillator(omega), state, scratch);
  }
  return std::abs(state.positions[0].x() - std::cos(omega * endTime));
}

/// A well-shaped body falling freely, floor off: every point follows x0 + g t^2 / 2.
double freeFallError(Integrator integrator, double h, double endTime)
{
  BodyDescription body;
  body.mesh = makeTetBox(2, 2, 2, 0.05, Vec3(0, 0, 1));
  SceneSettings scene;
  scene.integrator = integrator;
  scene.timeStep = h;
  MassSpringSimulation sim(body, scene);
  sim.advance(endTime);
  double worst = 0.0;
  for (std::size_t i = 0; i < sim.positions().size(); ++i)
  {
    const Vec3 exact = sim.restPositions()[i] + 0.5 * scene.gravity * endTime * endTime;
    worst = std::max(worst, (sim.positions()[i] - exact).norm());
  }
  return worst;
}

} // namespace

TEST(Integrators, FreeFallErrorHasTheMethodsOrder)
{
  const double g = 9.81, endTime = 0.5;
  for (Integrator integrator : kAll)
  {
    const double coarse = freeFallError(integrator, 1e-3, endTime);
    const double fine = freeFallError(integrator, 5e-4, endTime);
    if (integrator == Integrator::Euler || integrator == Integrator::EulerCromer)
    {
      // Both are first order here with the exact error g t h / 2 (Euler lags, Euler-Cromer leads).
      EXPECT_NEAR(coarse, 0.5 * g * endTime * 1e-3, 1e-9) << integratorName(integrator);
      EXPECT_NEAR(coarse / fine, 2.0, 1e-6) << integratorName(integrator);
    }
    else
    {
      // Midpoint and leapfrog Verlet integrate constant acceleration exactly.
      EXPECT_LT(coarse, 1e-12) << integratorName(integrator);
      EXPECT_LT(fine, 1e-12) << integratorName(integrator);
    }
  }
}

TEST(Integrators, HarmonicOscillatorConvergesAtTheExpectedOrder)
{
  for (Integrator integrator : kAll)
  {
    // Measured at 9/8 periods, where x crosses zero fastest: a whole period would hide the
    // phase error (x is at its maximum there) and show spurious super-convergence.
    const double coarse = oscillatorError(integrator, 1.0 / 400, 1.125);
    const double fine = oscillatorError(integrator, 1.0 / 800, 1.125);
    const double order = std::log2(coarse / fine);
    const bool secondOrder = integrator == Integrator::Midpoint || integrator == Integrator::Verlet;
    EXPECT_NEAR(order, secondOrder ? 2.0 : 1.0, 0.15) << integratorName(integrator);
  }
}

TEST(Integrators, SymplecticMethodsKeepOscillatorEnergyBounded)
{
  // 100 periods at 100 steps per period: Euler-Cromer and Verlet stay within a few percent of
  // the initial energy; explicit Euler gains energy every step.
  const double omega = 2.0 * M_PI, h = 1.0 / 100;
  for (Integrator integrator : kAll)
  {
    DynamicState state;
    state.positions = { Vec3(1, 0, 0) };
    state.velocities = { Vec3::Zero() };
    IntegratorScratch scratch;
    for (int s = 0; s < 10000; ++s)
    {
      integrateStep(integrator, h, Oscillator(omega), state, scratch);
    }
    const double x = state.positions[0].x(), v = state.velocities[0].x();
    const double energy = 0.5 * (v * v + omega * omega * x * x) / (0.5 * omega * omega);
    if (integrator == Integrator::Euler)
    {
      EXPECT_GT(energy, 10.0);
    }
    else if (integrator != Integrator::Midpoint)
    {
      EXPECT_NEAR(energy, 1.0, 0.1) << integratorName(integrator);
    }
  }
}
