// XPBD's error-controlled steps (pbd_step_control.cpp): on a hanging bar of Stable Neo-Hookean
// tets against an extrapolated fine-step reference, the achieved error follows the tolerance
// over two decades, looser tolerances take fewer steps, a first step too large is rejected, the
// steps land on the frame times and a resumed run takes the same steps; PBD, whose stiffness
// changes with the step, and bad tolerances are refused quoting the value.
#include "softbody/common/errors.h"
#include "softbody/mesh/mesh_generators.h"
#include "softbody/pbd/pbd_simulation.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

using namespace softbody;

namespace
{

/// A bar of 1 x 1 x 8 cells of 5 cm hanging from its top face, released from rest: it
/// stretches and oscillates about its static sag (about 1 cm).
Body hangingBar()
{
  const TetMesh mesh = makeTetBox(1, 1, 8, 0.05);
  Body body;
  body.mesh.points = mesh.points;
  body.mesh.tets = mesh.tets;
  body.material.model = MaterialModel::StableNeoHookean;
  body.material.physical = { 1.0e5, 0.3, 1000.0, 0.0 };
  body.material.massDistribution = MassDistribution::LumpedVolume;
  body.pinned = test::pointsWhere(mesh.points, [](const Vec3& p) { return p.z() > 0.4 - 1e-9; });
  return body;
}

PbdSettings xpbd()
{
  PbdSettings settings;
  settings.collisions.mode = CollisionMode::Off;
  settings.iterations = 20;
  settings.reportConvergence = false;
  return settings;
}

constexpr double kEndTime = 0.2;
constexpr int kFrames = 4;

std::vector<Vec3> run(PbdSimulation& sim)
{
  for (int frame = 1; frame <= kFrames; ++frame)
  {
    sim.advance(kEndTime * frame / kFrames);
    EXPECT_EQ(sim.time(), kEndTime * frame / kFrames); // the frame time, exactly
  }
  return sim.state().positions;
}

std::vector<Vec3> runFixed(double step)
{
  PbdSettings settings = xpbd();
  settings.timeStep = step;
  PbdSimulation sim(hangingBar(), settings);
  return run(sim);
}

} // namespace

TEST(XpbdErrorControl, HangingBarErrorFollowsTheTolerance)
{
  // XPBD's steps are first order: Richardson's 2 x(h/2) - x(h) from two fine runs removes the
  // leading error term, leaving a reference far more accurate than the tolerances asked for.
  const std::vector<Vec3> coarse = runFixed(1.0e-4), fine = runFixed(5.0e-5);
  std::vector<Vec3> reference(fine.size());
  for (std::size_t i = 0; i < fine.size(); ++i)
  {
    reference[i] = 2.0 * fine[i] - coarse[i];
  }
  std::printf("reference: the fine runs differ by %.2e m\n", test::maxDistance(fine, coarse));
  unsigned long long previousSteps = 0;
  for (double tolerance : { 1e-2, 1e-3, 1e-4 })
  {
    PbdSettings settings = xpbd();
    settings.stepControl = StepControl::ErrorControlled;
    settings.errorTolerance = tolerance;
    PbdSimulation sim(hangingBar(), settings);
    const double error = test::maxDistance(run(sim), reference);
    const StepControlReport& report = *sim.stepControlReport();
    std::printf("tolerance %.0e m/s: error %.2e m in %llu steps; last frame %llu steps of %.2e to "
                "%.2e s (%llu rejected)\n", tolerance, error, sim.stepCount(), report.acceptedSteps,
      report.smallestStep, report.largestStep, report.rejectedSteps);
    EXPECT_LT(error, 2.0 * tolerance * kEndTime) << tolerance;
    EXPECT_GT(error, 0.01 * tolerance * kEndTime) << tolerance << ": far more steps than needed";
    EXPECT_EQ(report.stepsOverTolerance, 0u);
    if (previousSteps > 0)
    {
      EXPECT_GT(sim.stepCount(), 2 * previousSteps) << "a tighter tolerance took hardly more steps";
    }
    previousSteps = sim.stepCount();
  }
}

TEST(XpbdErrorControl, AFirstStepTooLargeIsRejectedAndAResumedRunTakesTheSameSteps)
{
  PbdSettings settings = xpbd();
  settings.stepControl = StepControl::ErrorControlled;
  settings.errorTolerance = 1e-3;
  PbdSimulation straight(hangingBar(), settings), resumed(hangingBar(), settings);
  straight.advance(0.1);
  EXPECT_GT(straight.stepControlReport()->rejectedSteps, 0u) << "a step of the whole 0.1 s was accepted";
  resumed.advance(0.05);
  const DynamicState snapshot = resumed.state();
  resumed.advance(0.1);
  PbdSimulation replay(hangingBar(), settings);
  replay.restoreState(snapshot);
  replay.advance(0.1);
  EXPECT_EQ(replay.state().positions, resumed.state().positions);
}

TEST(XpbdErrorControl, TheUsersTimeStepBoundsTheSteps)
{
  PbdSettings settings = xpbd();
  settings.stepControl = StepControl::ErrorControlled;
  settings.errorTolerance = 1.0; // loose: the bound decides
  settings.timeStep = 0.01;
  PbdSimulation sim(hangingBar(), settings);
  sim.advance(0.1);
  // (the last step of an advance is what is left to its end time: 0.01 to rounding)
  EXPECT_LE(sim.stepControlReport()->largestStep, 0.01 * (1.0 + 1e-12));
  EXPECT_GE(sim.stepCount(), 10u);
}

TEST(XpbdErrorControl, PbdAndBadTolerancesAreRefusedQuotingTheValue)
{
  PbdSettings pbd = xpbd();
  pbd.formulation = PbdFormulation::Pbd;
  pbd.stepControl = StepControl::ErrorControlled;
  Body body = hangingBar();
  body.material.model = MaterialModel::SpringNetwork;
  const std::string message = test::refusalOf<PbdSimulation>(body, pbd);
  EXPECT_NE(message.find("TimeStepMode 1"), std::string::npos) << message;
  EXPECT_NE(message.find("XPBD"), std::string::npos) << message;
  for (double tolerance : { 0.0, -1e-3 })
  {
    PbdSettings settings = xpbd();
    settings.stepControl = StepControl::ErrorControlled;
    settings.errorTolerance = tolerance;
    const std::string refusal = test::refusalOf<PbdSimulation>(hangingBar(), settings);
    EXPECT_NE(refusal.find("ErrorTolerance"), std::string::npos) << refusal;
    EXPECT_NE(refusal.find(tolerance == 0.0 ? "0" : "-0.001"), std::string::npos) << refusal;
  }
}
