// BDF2, the second-order implicit integrator (bdf2.h): its measured order on a linear
// oscillator (against the exact solution) and on a cantilever of each material model (against a
// fine-step reference), against Implicit Euler's first order; its closed-form step; and its
// stability at frame-rate steps on a stiff body.
#include "softbody/massspring/bdf2.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"
#include "spring_oscillator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <map>

using namespace softbody;

namespace
{

/// The shared spring (spring_oscillator.h) with the error of a run of each implicit integrator.
struct LinearOscillator : test::SpringOscillator
{
  /// |x(T) - exact| after steps of h with the integrator (Bdf2 or ImplicitEuler).
  double error(Integrator integrator, double h, double endTime) const
  {
    const BodyElements elements = this->elements();
    std::unique_ptr<ImplicitIntegrator> stepper;
    if (integrator == Integrator::Bdf2)
    {
      stepper = std::make_unique<Bdf2Stepper>(topology, elements, masses, restPositions, scene);
    }
    else
    {
      stepper = std::make_unique<ImplicitEulerStepper>(topology, elements, masses, restPositions, scene);
    }
    DynamicState state;
    state.positions = { Vec3::Zero(), Vec3(l0 + amplitude, 0, 0) };
    state.velocities = { Vec3::Zero(), Vec3::Zero() };
    StepPlan plan;
    const int steps = static_cast<int>(std::lround(endTime / h));
    for (int s = 0; s < steps; ++s)
    {
      stepper->step(h, state, plan);
      state.time += h; // the caller's, as MassSpringSimulation does
      state.previousStep = h;
    }
    return std::abs(state.positions[1].x() - exact(state.time));
  }
};

/// The order measured from errors at h, h/2, h/4: log2 of the last ratio.
double measuredOrder(const std::vector<double>& errors)
{
  return std::log2(errors[errors.size() - 2] / errors.back());
}

} // namespace

// A constant-step BDF2 step on the linear spring is the recursion
//   x+ - 4/3 x + 1/3 x- = 2/3 h v+,   v+ - 4/3 v + 1/3 v- = 2/3 h a(x+),
// solved here in closed form; the stepper's second step (its first has no history) must land on it.
TEST(Bdf2, SecondStepEqualsTheClosedFormBdf2Update)
{
  const LinearOscillator o;
  const BodyElements elements{ MaterialModel::SpringNetwork, &o.constants, nullptr };
  Bdf2Stepper stepper(o.topology, elements, o.masses, o.restPositions, o.scene);
  const double h = 0.01;
  DynamicState state;
  state.positions = { Vec3::Zero(), Vec3(o.l0 + o.amplitude, 0, 0) };
  state.velocities = { Vec3::Zero(), Vec3(0.3, 0, 0) };
  StepPlan plan;
  stepper.step(h, state, plan); // backward Euler: no history yet
  state.time += h;
  state.previousStep = h;
  const double x = state.positions[1].x(), v = state.velocities[1].x();
  const double xm = state.previousPositions[1].x(), vm = state.previousVelocities[1].x();
  // y = x^ + b v^ with b = 2h/3, x^ = 4/3 x - 1/3 x-, v^ likewise; v+ = (x+ - x^) / b and
  // m (v+ - v^) = -b k (x+ - L): x+ = (m (x^ + b v^) + b^2 k L) / (m + b^2 k).
  const double b = 2.0 * h / 3.0;
  const double xh = 4.0 / 3.0 * x - 1.0 / 3.0 * xm, vh = 4.0 / 3.0 * v - 1.0 / 3.0 * vm;
  const double x1 = (o.m * (xh + b * vh) + b * b * o.k * o.l0) / (o.m + b * b * o.k);
  const double v1 = (x1 - xh) / b;
  stepper.step(h, state, plan);
  EXPECT_NEAR(state.positions[1].x(), x1, 1e-14);
  EXPECT_NEAR(state.velocities[1].x(), v1, 1e-11);
  EXPECT_EQ(state.previousPositions[1].x(), x); // the history moved on by one step
}

TEST(Bdf2, LinearOscillatorConvergesAtSecondOrderWhereImplicitEulerIsFirst)
{
  const LinearOscillator o;
  const double endTime = 0.5; // about 3 periods (w = 40 rad/s)
  for (Integrator integrator : { Integrator::Bdf2, Integrator::ImplicitEuler })
  {
    std::vector<double> errors;
    for (double h : { 1.0 / 1600.0, 1.0 / 3200.0, 1.0 / 6400.0 })
    {
      errors.push_back(o.error(integrator, h, endTime));
    }
    const double order = measuredOrder(errors);
    std::cout << integratorName(integrator) << ": errors " << errors[0] << " .. " << errors.back()
              << ", measured order " << order << "\n";
    EXPECT_NEAR(order, factsOf(integrator).order, 0.15) << integratorName(integrator);
  }
  // At the same step BDF2 is far more accurate than backward Euler.
  EXPECT_LT(o.error(Integrator::Bdf2, 1.0 / 1600.0, endTime),
    0.1 * o.error(Integrator::ImplicitEuler, 1.0 / 1600.0, endTime));
}

// A cantilever of 10 x 2 x 2 cells, its x = 0 face pinned, released from rest under gravity: its
// positions at 0.1 s (the largest distance over the points) against a reference run at 1/32
// of the coarsest step, for the spring network and the continuum models. BDF2 converges at
// second order for each.
TEST(Bdf2, CantileverConvergesAtSecondOrderForEveryMaterialModel)
{
  for (MaterialModel model :
    { MaterialModel::SpringNetwork, MaterialModel::Corotated, MaterialModel::StableNeoHookean })
  {
    Body body;
    body.mesh = makeTetBox(10, 2, 2, 0.02, Vec3(0, 0, 1));
    body.material.model = model;
    body.material.physical.dampingTime = 0.0;
    body.pinned.assign(body.mesh.points.size(), 0);
    for (std::size_t i = 0; i < body.mesh.points.size(); ++i)
    {
      body.pinned[i] = body.mesh.points[i].x() < 1e-9 ? 1 : 0;
    }
    const auto positionsAt = [&](double h) {
      SceneSettings scene;
      scene.integrator = Integrator::Bdf2;
      scene.timeStep = h;
      scene.implicit.tolerance = 1e-10;
      scene.implicit.maxIterations = 100;
      MassSpringSimulation sim(body, scene);
      sim.advance(0.1);
      return sim.positions();
    };
    const double coarse = 1.0 / 1000.0;
    const std::vector<Vec3> reference = positionsAt(coarse / 32.0);
    std::vector<double> errors;
    for (double h : { coarse, coarse / 2.0, coarse / 4.0 })
    {
      const std::vector<Vec3> x = positionsAt(h);
      double error = 0.0;
      for (std::size_t i = 0; i < x.size(); ++i)
      {
        error = std::max(error, (x[i] - reference[i]).norm());
      }
      errors.push_back(error);
    }
    const double order = measuredOrder(errors);
    std::cout << materialModelName(model) << ": error " << errors[0] << " .. " << errors.back()
              << " m, measured order " << order << "\n";
    // Measured: 2.00 for the network, 1.72 for the continuum models (from 1 ms steps).
    EXPECT_GT(order, 1.6) << materialModelName(model);
    EXPECT_LT(order, 2.4) << materialModelName(model);
  }
}

// Stiff steel (first bending mode ~1 ms) at steps of 25 us, undamped, released from rest
// under gravity: the energy kinetic + elastic + gravity's potential is conserved by the exact
// motion; both integrators are stable, and BDF2 loses far less of it than backward Euler.
TEST(Bdf2, StiffCantileverLosesFarLessEnergyThanImplicitEuler)
{
  Body body;
  body.mesh = makeTetBox(10, 2, 2, 0.02, Vec3(0, 0, 1));
  body.material.physical.youngsModulus = 2e11;
  body.material.physical.density = 7850.0;
  body.material.physical.dampingTime = 0.0;
  body.pinned.assign(body.mesh.points.size(), 0);
  for (std::size_t i = 0; i < body.mesh.points.size(); ++i)
  {
    body.pinned[i] = body.mesh.points[i].x() < 1e-9 ? 1 : 0;
  }
  std::map<Integrator, double> loss;
  for (Integrator integrator : { Integrator::Bdf2, Integrator::ImplicitEuler })
  {
    SceneSettings scene;
    scene.integrator = integrator;
    scene.timeStep = 2.5e-5;
    // Steel at steps this short: Phi's decrease near 1e-6 of gravity's residual is below its
    // rounding (it scales with h^2, and BDF2 solves steps of 2h/3).
    scene.implicit.tolerance = 1e-4;
    MassSpringSimulation sim(body, scene);
    ASSERT_NO_THROW(sim.advance(0.005)) << integratorName(integrator);
    ASSERT_EQ(sim.implicitConvergence()->unconvergedSteps, 0u) << integratorName(integrator) << ": residual " << sim.implicitConvergence()->residual;
    double potential = 0.0, elastic = sim.elasticEnergy(); // gravity's, from the start
    for (std::size_t i = 0; i < body.mesh.points.size(); ++i)
    {
      ASSERT_TRUE(sim.positions()[i].allFinite());
      potential += sim.masses()[i] * 9.81 * (sim.positions()[i].z() - body.mesh.points[i].z());
    }
    // Released from rest, the exact motion's largest elastic energy is twice the static one:
    // the loss is measured against the energy the vibration holds.
    loss[integrator] = -(elastic + sim.kineticEnergy() + potential) / (-potential);
  }
  std::cout << "energy lost in 0.005 s at 25 us steps: BDF2 " << loss[Integrator::Bdf2]
            << ", Implicit Euler " << loss[Integrator::ImplicitEuler] << " of gravity's work\n";
  EXPECT_LT(loss[Integrator::Bdf2], 0.3 * loss[Integrator::ImplicitEuler]);
  EXPECT_GT(loss[Integrator::Bdf2], -1e-3); // no energy made
}
