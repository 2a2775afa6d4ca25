// Error-controlled time steps (common/error_control.h): on a spring against its exact motion and
// on a hanging bar against a fine-step reference, the achieved error stays within the tolerance
// over decades of tolerances, for implicit and explicit integrators; a step too large is
// rejected and reported; the steps land on the frame times; bad tolerances are refused quoting
// the value.
#include "softbody/common/error_control.h"
#include "softbody/common/errors.h"
#include "softbody/massspring/bdf2.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"
#include "spring_oscillator.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

using namespace softbody;

namespace
{

using Spring = test::SpringOscillator;

/// A bar of 2 x 2 x 10 cells hanging from its pinned top face, released from rest: it stretches
/// and oscillates about its static elongation.
BodyDescription hangingBar()
{
  BodyDescription body;
  body.mesh = makeTetBox(2, 2, 10, 0.02, Vec3(0, 0, 1));
  body.material.physical.dampingTime = 0.0;
  body.pinned.assign(body.mesh.points.size(), 0);
  for (std::size_t i = 0; i < body.mesh.points.size(); ++i)
  {
    body.pinned[i] = body.mesh.points[i].z() > 1.2 - 1e-9 ? 1 : 0;
  }
  return body;
}

} // namespace

// The controller on the spring with BDF2 and Implicit Euler steps: over one second (frames of
// 0.1 s, each a separate advance), the error against the exact motion stays within twice the
// tolerance (error per simulated second) for tolerances from 1e-3 m to 1e-6 m.
TEST(ErrorControl, SpringMeetsTheToleranceAgainstItsExactMotion)
{
  const Spring o;
  const BodyElements elements{ MaterialModel::SpringNetwork, &o.constants, nullptr };
  for (Integrator integrator : { Integrator::Bdf2, Integrator::ImplicitEuler })
  {
    for (double tolerance : { 1e-3, 1e-4, 1e-5, 1e-6 })
    {
      if (integrator == Integrator::ImplicitEuler && tolerance < 1e-4)
      {
        continue; // first order: ~1e6 steps
      }
      std::unique_ptr<ImplicitIntegrator> stepper;
      if (integrator == Integrator::Bdf2)
      {
        stepper = std::make_unique<Bdf2Stepper>(o.topology, elements, o.masses, o.restPositions, o.scene);
      }
      else
      {
        stepper = std::make_unique<ImplicitEulerStepper>(o.topology, elements, o.masses, o.restPositions, o.scene);
      }
      DynamicState state;
      state.positions = { Vec3::Zero(), Vec3(o.l0 + o.amplitude, 0, 0) };
      state.velocities = { Vec3::Zero(), Vec3::Zero() };
      StepPlan plan;
      const auto takeStep = [&](double h) {
        stepper->step(h, state, plan);
        state.time += h;
        state.previousStep = h;
        ++state.stepCount;
      };
      ErrorControl control{ tolerance, factsOf(integrator).order };
      control.halvesErrorFactor = integrator == Integrator::Bdf2 ? bdf2HalvesErrorFactor : nullptr;
      StepControlReport report;
      double worst = 0.0;
      unsigned long long accepted = 0, rejected = 0;
      for (int frame = 1; frame <= 10; ++frame)
      {
        advanceWithErrorControl(state, control, 0.1 * frame, {}, takeStep, [] {}, [](std::vector<char>&) {}, report);
        EXPECT_EQ(state.time, 0.1 * frame); // the frame time, exactly
        worst = std::max(worst, std::abs(state.positions[1].x() - o.exact(state.time)));
        accepted += report.acceptedSteps;
        rejected += report.rejectedSteps;
        EXPECT_EQ(report.stepsOverTolerance, 0u);
      }
      std::cout << integratorName(integrator) << " at " << tolerance << " m/s: error " << worst
                << " m over 1 s in " << accepted << " steps (" << rejected << " rejected)\n";
      // The estimate is of each step's error; on an undamped oscillator the phase errors they
      // leave grow with the run (measured over 1 s: 0.8 to 1.7 times the tolerance).
      EXPECT_LT(worst, 2.0 * tolerance) << integratorName(integrator) << " at " << tolerance;
      // Not far too accurate either: the steps are not much shorter than the tolerance needs.
      EXPECT_GT(worst, 0.01 * tolerance) << integratorName(integrator) << " at " << tolerance;
      // The first frame's step (its whole interval) was too large, and was said to be.
      EXPECT_GT(rejected, 0u);
    }
  }
}

// The hanging bar through MassSpringSimulation: BDF2, Implicit Euler and Verlet (an explicit
// integrator, whose steps stay within its stable step) with error-controlled steps against a
// BDF2 reference at a fixed step 1/16 of the smallest the controller took.
TEST(ErrorControl, HangingBarMeetsTheToleranceWithImplicitAndExplicitIntegrators)
{
  const BodyDescription body = hangingBar();
  const double endTime = 0.3;
  const auto run = [&](SceneSettings scene) {
    scene.implicit.tolerance = 1e-10;
    scene.implicit.maxIterations = 100;
    auto sim = std::make_unique<MassSpringSimulation>(body, scene);
    for (int frame = 1; frame <= 6; ++frame)
    {
      sim->advance(endTime * frame / 6.0);
    }
    return sim;
  };
  SceneSettings referenceScene;
  referenceScene.integrator = Integrator::Bdf2;
  referenceScene.timeStep = 2.0e-5;
  const std::vector<Vec3> reference = run(referenceScene)->positions();
  struct Case
  {
    Integrator integrator;
    double tolerance;
  };
  for (const Case& c : { Case{ Integrator::Bdf2, 1e-3 }, Case{ Integrator::Bdf2, 1e-5 },
         Case{ Integrator::ImplicitEuler, 1e-3 }, Case{ Integrator::Verlet, 1e-4 } })
  {
    SceneSettings scene;
    scene.integrator = c.integrator;
    scene.stepControl = StepControl::ErrorControlled;
    scene.errorTolerance = c.tolerance;
    const auto sim = run(scene);
    const double error = test::maxDistance(sim->positions(), reference);
    const StepControlReport& report = *sim->stepControlReport();
    std::cout << integratorName(c.integrator) << " at " << c.tolerance << " m/s: error " << error
              << " m; last frame " << report.acceptedSteps << " steps of " << report.smallestStep << " to "
              << report.largestStep << " s, estimate " << report.estimatedError << " m\n";
    EXPECT_LT(error, c.tolerance) << integratorName(c.integrator);
    EXPECT_GT(report.acceptedSteps, 0u);
    EXPECT_EQ(report.stepsOverTolerance, 0u);
    if (!isImplicit(c.integrator))
    {
      EXPECT_LE(report.largestStep, sim->estimatedStableStep()) << "above the stable step";
    }
  }
}

// A snapshot resumes the same steps (the controller's proposal is part of the state), so the
// frame cache's replay equals an uninterrupted run.
TEST(ErrorControl, AResumedRunTakesTheSameSteps)
{
  SceneSettings scene;
  scene.integrator = Integrator::Bdf2;
  scene.stepControl = StepControl::ErrorControlled;
  scene.errorTolerance = 1e-4;
  MassSpringSimulation straight(hangingBar(), scene), resumed(hangingBar(), scene);
  straight.advance(0.1);
  resumed.advance(0.05);
  const DynamicState snapshot = resumed.state();
  resumed.advance(0.1);
  MassSpringSimulation replay(hangingBar(), scene);
  replay.restoreState(snapshot);
  replay.advance(0.1);
  EXPECT_EQ(replay.positions(), resumed.positions());
  EXPECT_GT(straight.stepCount(), 0u);
}

TEST(ErrorControl, BadTolerancesAndTheStaticSolveAreRefusedQuotingTheValue)
{
  for (double tolerance : { 0.0, -1e-3, std::nan(""), 1e-20 })
  {
    SceneSettings scene;
    scene.integrator = Integrator::Bdf2;
    scene.stepControl = StepControl::ErrorControlled;
    scene.errorTolerance = tolerance;
    try
    {
      MassSpringSimulation sim(hangingBar(), scene);
      ADD_FAILURE() << "tolerance " << tolerance << " accepted";
    }
    catch (const InvalidInputError& e)
    {
      const std::string message = e.what();
      EXPECT_NE(message.find("ErrorTolerance"), std::string::npos) << message;
      EXPECT_NE(message.find(tolerance == 1e-20 ? "1e-20" : tolerance == 0.0 ? "0" : tolerance < 0 ? "-0.001" : "nan"),
        std::string::npos)
        << message;
    }
  }
  SceneSettings scene;
  scene.integrator = Integrator::Static;
  scene.stepControl = StepControl::ErrorControlled;
  EXPECT_THROW(MassSpringSimulation(hangingBar(), scene), InvalidInputError);
}
