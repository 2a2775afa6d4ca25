// The four integrators against analytic solutions: free fall and the harmonic oscillator.
#include "softbody/integrators/explicit_integrators.h"
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
  void evaluate(double, const std::vector<Vec3>& x, const std::vector<Vec3>&, std::vector<Vec3>& a) const override
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
  Body body;
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

TEST(Integrators, OscillatorEnergyFollowsEachMethodsAmplification)
{
  // 100 periods at 100 steps per period (omega h = 2 pi / 100), from x = 1, v = 0. Each method's
  // energy E = (v^2 + omega^2 x^2) / 2 is known in closed form:
  //   Euler:    E_{n+1} = (1 + (omega h)^2) E_n           exactly (|A|^2 of a normal map)
  //   Midpoint: E_{n+1} = (1 + (omega h)^4 / 4) E_n       exactly: 1.0397 after 10^4 steps
  //   Euler-Cromer and leapfrog Verlet conserve H = E - h omega^2 x v / 2 exactly (their
  //   modified energy), so E itself stays within about omega h / 2 = 3.1% of it, forever.
  const double omega = 2.0 * M_PI, h = 1.0 / 100, wh = omega * h;
  const int steps = 10000;
  for (Integrator integrator : kAll)
  {
    DynamicState state;
    state.positions = { Vec3(1, 0, 0) };
    state.velocities = { Vec3::Zero() };
    IntegratorScratch scratch;
    auto energy = [&] {
      const double x = state.positions[0].x(), v = state.velocities[0].x();
      return 0.5 * (v * v + omega * omega * x * x);
    };
    auto modified = [&] {
      const double x = state.positions[0].x(), v = state.velocities[0].x();
      return energy() - 0.5 * h * omega * omega * x * v;
    };
    const double e0 = energy();
    double lowest = e0, highest = e0, h0 = 0.0, worstModified = 0.0;
    for (int s = 0; s < steps; ++s)
    {
      integrateStep(integrator, h, Oscillator(omega), state, scratch);
      lowest = std::min(lowest, energy());
      highest = std::max(highest, energy());
      if (s == 0)
      {
        h0 = modified(); // Verlet's first step is a half kick: H is conserved from then on
      }
      worstModified = std::max(worstModified, std::abs(modified() / h0 - 1.0));
    }
    const double ratio = energy() / e0;
    switch (integrator)
    {
      case Integrator::Euler:
        EXPECT_NEAR(std::log(ratio), steps * std::log1p(wh * wh), 1e-9) << ratio;
        break;
      case Integrator::Midpoint:
        EXPECT_NEAR(ratio, std::pow(1.0 + std::pow(wh, 4) / 4.0, steps), 1e-10) << ratio;
        EXPECT_NEAR(ratio, 1.0397, 1e-4); // the measured drift, stated
        break;
      case Integrator::Verlet:
      case Integrator::EulerCromer:
        EXPECT_LT(worstModified, 1e-12) << integratorName(integrator);
        // Measured: E in [0.9686, 1.0324] (Euler-Cromer), [0.9686, 1.0314] (Verlet).
        EXPECT_GT(lowest / e0, 1.0 - 0.52 * wh) << integratorName(integrator);
        EXPECT_LT(highest / e0, 1.0 + 0.52 * wh) << integratorName(integrator);
        break;
      case Integrator::ImplicitEuler:
      case Integrator::ProjectiveDynamics:
      case Integrator::Static:
      case Integrator::Bdf2:
      case Integrator::VertexBlockDescent:
        FAIL() << "explicit integrators only (test_implicit.cpp, test_bdf2.cpp and test_vertex_block_descent.cpp cover the implicit ones)";
    }
  }
}

TEST(Integrators, VerletIsExactInFreeFallAcrossStepSizeChanges)
{
  // Leapfrog with a variable step kicks by the mean of the previous and the current step; then
  // it integrates a constant acceleration exactly whatever the steps. advance() splits each
  // interval into equal steps, so these intervals change the step: 1 ms, then 0.9875 ms (24
  // steps over 23.7 ms), then 0.8333 ms (3 steps over 2.5 ms), then 1 ms again.
  Body body;
  body.mesh = makeTetBox(2, 2, 2, 0.05, Vec3(0, 0, 1));
  SceneSettings scene;
  scene.integrator = Integrator::Verlet;
  scene.timeStep = 1e-3;
  MassSpringSimulation sim(body, scene);
  const double g = scene.gravity.z();
  for (double t : { 0.1, 0.1237, 0.1262, 0.2262 })
  {
    sim.advance(t);
    for (std::size_t i = 0; i < sim.positions().size(); ++i)
    {
      const Vec3 exact = sim.restPositions()[i] + Vec3(0, 0, 0.5 * g * t * t);
      ASSERT_LT((sim.positions()[i] - exact).norm(), 1e-12) << "t = " << t;
    }
  }
  EXPECT_EQ(sim.stepCount(), 100u + 24u + 3u + 100u);
}
