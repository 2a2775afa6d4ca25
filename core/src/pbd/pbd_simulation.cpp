#include "softbody/pbd/pbd_simulation.h"
#include "softbody/mesh/volume_ratios.h"
#include "softbody/material/tet_elastic_forces.h"

#include "softbody/common/errors.h"
#include "softbody/common/parallel.h"
#include "softbody/common/stepping.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>

namespace softbody
{

void PbdSimulation::restoreState(const DynamicState& snapshot)
{
  if (snapshot.positions.size() != State.positions.size() ||
    snapshot.linkRestLengths.size() != State.linkRestLengths.size())
  {
    throw InvalidInputError("The snapshot does not belong to this simulation.");
  }
  const bool bounces = !State.impactSpeeds.empty();
  State = snapshot;
  if (bounces && (State.impactSpeeds.size() != State.positions.size() ||
                   State.impactNormals.size() != State.positions.size()))
  {
    // a snapshot from before bounces
    State.impactSpeeds.assign(State.positions.size(), 0.0);
    State.impactNormals.assign(State.positions.size(), Vec3::Zero());
  }
  LinkStateStale = false;
  if (!State.linkRestLengths.empty())
  {
    Links.rest = State.linkRestLengths;
    Links.broken = State.linkBroken;
    markBrokenTets();
  }
}

void PbdSimulation::prepareParameters(double h)
{
  if (h == ParametersStep)
  {
    return;
  }
  ParametersStep = h;
  // SOR scales each projection; Jacobi applies its relaxation when averaging instead.
  const double relaxation = Settings.solver == PbdSolver::Jacobi ? 1.0 : Settings.relaxation;
  const bool xpbd = Settings.formulation == PbdFormulation::Xpbd;
  auto parameters = [&](const ConstraintMaterial& material, double factor, double compliance = -1.0) {
    ProjectionParameters p;
    if (xpbd)
    {
      // A per-element compliance (from elasticity) replaces the batch's; an infinite one is a
      // constraint of zero stiffness.
      const double alpha = compliance >= 0.0 ? compliance : material.compliance / factor;
      p.scale = std::isinf(alpha) ? 0.0 : relaxation;
      p.alphaTilde = std::isinf(alpha) ? 0.0 : alpha / (h * h);
    }
    else
    {
      p.scale = relaxation *
        pbdStiffnessPerIteration(std::min(1.0, material.stiffness * factor), Settings.iterations);
    }
    return p;
  };
  Links.params.resize(Links.size());
  for (std::size_t c = 0; c < Links.size(); ++c)
  {
    Links.params[c] = parameters(Settings.links, Links.stiffnessScale[c],
      Links.compliance.empty() ? -1.0 : Links.compliance[c]);
  }
  Volumes.params.resize(Volumes.size());
  for (std::size_t t = 0; t < Volumes.size(); ++t)
  {
    Volumes.params[t] = parameters(Settings.volumes, 1.0, Volumes.compliance.empty() ? -1.0 : Volumes.compliance[t]);
  }
  Attachments.params.assign(Attachments.size(), parameters(Settings.attachments, 1.0));
  TetElastic.params.resize(TetElastic.size());
  for (std::size_t t = 0; t < TetElastic.size(); ++t)
  {
    TetElasticParameters& p = TetElastic.params[t];
    p.scale = relaxation;
    p.alphaTildeDeviatoric = TetElastic.deviatoricCompliance[t] / (h * h);
    p.alphaTildeHydrostatic = TetElastic.hydrostaticCompliance[t] / (h * h); // inf stays inf
  }
}

void PbdSimulation::predict(double h)
{
  ScopedStageTimer timer(Plan, Stage::Predict);
  const double keep = std::max(0.0, 1.0 - Settings.damping * h);
  const Vec3 g = Settings.gravity;
  const bool verlet = Settings.prediction == PbdPrediction::Verlet;
  Predicted.resize(State.positions.size());
  VelocityBefore.resize(State.positions.size());
  // The conditions' loads at the substep's start, as external accelerations.
  const bool loads = Conditions.hasLoads();
  if (loads)
  {
    LoadForce.assign(State.positions.size(), Vec3::Zero());
    Conditions.addLoads(SubstepTime, State.positions, LoadForce);
  }
  parallelFor(State.positions.size(), 1024, [&](std::size_t i) {
    const Vec3& x = State.positions[i];
    if (InverseMass[i] == 0.0)
    {
      Predicted[i] = x;
      VelocityBefore[i].setZero();
      return;
    }
    const Vec3 a = loads ? Vec3(g + InverseMass[i] * LoadForce[i]) : g;
    if (verlet)
    {
      // Position Verlet: the drift is the last step's displacement over h (stored as the
      // velocity), the acceleration enters as h^2 a.
      Predicted[i] = x + keep * h * State.velocities[i] + (h * h) * a;
      VelocityBefore[i] = (Predicted[i] - x) / h;
    }
    else
    {
      const Vec3 v = keep * (State.velocities[i] + h * a);
      VelocityBefore[i] = v;
      Predicted[i] = x + h * v;
    }
  });
  holdPredicted(h);
  std::fill(Links.lambda.begin(), Links.lambda.end(), 0.0);
  std::fill(Volumes.lambda.begin(), Volumes.lambda.end(), 0.0);
  std::fill(TetElastic.lambda.begin(), TetElastic.lambda.end(), TetElasticMultipliers::Zero());
  std::fill(Attachments.lambda.begin(), Attachments.lambda.end(), 0.0);
}

bool PbdSimulation::setConditionValues(const std::vector<Condition>& conditions)
{
  if (!Conditions.sameStructure(conditions))
  {
    return false;
  }
  Conditions.replaceValues(conditions);
  return true;
}

void PbdSimulation::holdPredicted(double h)
{
  // Held components where their conditions put them at the substep's end, before the
  // constraints see them (and again after: a roller's free components move, its held ones not).
  if (!Conditions.heldAxes().empty())
  {
    Conditions.holdPositions(SubstepTime + h, Predicted);
  }
}

void PbdSimulation::projectAll(Stage stage)
{
  ScopedStageTimer timer(Plan, stage);
  std::vector<Vec3>& x = Predicted;
  const std::vector<double>& w = InverseMass;
  auto sweepBatch = [&](auto& batch, const BatchSchedule& schedule) {
    switch (Settings.solver)
    {
      case PbdSolver::GaussSeidel:
        gaussSeidelSweep(batch, schedule, x, w);
        break;
      case PbdSolver::ParallelGaussSeidel:
        coloredGaussSeidelSweep(batch, schedule, x, w);
        break;
      case PbdSolver::Jacobi:
        jacobiSweep(batch, schedule, Settings.relaxation, x, w, JacobiScratch);
        break;
    }
  };
  switch (stage)
  {
    case Stage::SolveLinks:
      sweepBatch(Links, LinkSchedule);
      break;
    case Stage::SolveTetElasticity:
      sweepBatch(TetElastic, VolumeSchedule); // the same tets in the same order as Volumes
      break;
    case Stage::SolveVolumes:
      sweepBatch(Volumes, VolumeSchedule);
      break;
    case Stage::SolveAttachments:
      sweepBatch(Attachments, AttachmentSchedule);
      break;
    default:
      break;
  }
}

void PbdSimulation::sweep()
{
  // One iteration: the planned constraint types in a fixed order (links, continuum tets,
  // volumes, pins), then the contacts, so each iteration ends with the inequalities satisfied.
  for (Stage stage : { Stage::SolveLinks, Stage::SolveTetElasticity, Stage::SolveVolumes, Stage::SolveAttachments })
  {
    if (Plan.runs(stage))
    {
      projectAll(stage);
    }
  }
  if (Plan.runs(Stage::SolveContacts))
  {
    projectContacts();
  }
}

double PbdSimulation::residual() const
{
  ScopedStageTimer timer(Plan, Stage::Residual);
  ++ResidualEvaluations;
  const std::vector<Vec3>& x = Predicted;
  // Only the constraint types the step solves: one of zero stiffness asks for nothing.
  double sum = 0.0;
  if (Plan.runs(Stage::SolveLinks))
  {
    sum += squaredResidual(Links, x, InverseMass);
  }
  if (Plan.runs(Stage::SolveTetElasticity))
  {
    sum += squaredResidual(TetElastic, x, InverseMass);
  }
  if (Plan.runs(Stage::SolveVolumes))
  {
    sum += squaredResidual(Volumes, x, InverseMass);
  }
  if (Plan.runs(Stage::SolveAttachments))
  {
    sum += squaredResidual(Attachments, x, InverseMass);
  }
  if (Plan.runs(Stage::SolveContacts))
  {
    sum += contactResidual();
  }
  return std::sqrt(sum);
}

void PbdSimulation::solve(bool recordResiduals)
{
  const bool checkTolerance = Settings.residualTolerance > 0.0;
  Convergence.residualHistory.clear();
  Convergence.iterations = 0;
  for (int it = 0; it < Settings.iterations; ++it)
  {
    sweep();
    Convergence.iterations = it + 1;
    if (checkTolerance || recordResiduals)
    {
      const double r = residual();
      Convergence.residual = r;
      if (recordResiduals)
      {
        Convergence.residualHistory.push_back(r);
      }
      if (checkTolerance && r < Settings.residualTolerance)
      {
        break;
      }
    }
  }
  if (Plan.runs(Stage::SolveContacts))
  {
    ScopedStageTimer timer(Plan, Stage::SolveContacts);
    finishHeldTets();
  }
}

void PbdSimulation::updateVelocities(double h)
{
  ScopedStageTimer timer(Plan, Stage::UpdateVelocities);
  parallelFor(State.positions.size(), 1024, [&](std::size_t i) {
    State.velocities[i] = (Predicted[i] - State.positions[i]) / h;
    State.positions[i] = Predicted[i];
  });
}

void PbdSimulation::substep(double h, bool recordResiduals)
{
  prepareParameters(h);
  predict(h);
  if (Plan.runs(Stage::CollisionDetect))
  {
    detectContacts(h);
  }
  solve(recordResiduals);
  holdPredicted(h);
  updateVelocities(h);
  if (Plan.runs(Stage::ContactResponse))
  {
    applyContactResponse(h);
  }
  Conditions.holdPoints(SubstepTime + h, State.positions, State.velocities);
  if (Plan.runs(Stage::UpdateLinks))
  {
    updateLinks(h);
  }
}

void PbdSimulation::step(double h)
{
  stepOnce(h, Plan.runs(Stage::Residual));
}

void PbdSimulation::stepOnce(double h, bool recordConvergence)
{
  const double hs = h / Settings.substeps;
  for (int s = 0; s < Settings.substeps; ++s)
  {
    SubstepTime = State.time + s * hs;
    substep(hs, RecordEveryStep || (recordConvergence && s + 1 == Settings.substeps));
  }
  if (ReactionsFromMultipliers)
  {
    recordSupportForces(hs); // the multipliers still hold the last substep's
  }
  State.time += h;
  ++State.stepCount;
  LinkStateStale = !State.linkRestLengths.empty();
}

const DynamicState& PbdSimulation::state() const
{
  if (LinkStateStale)
  {
    State.linkRestLengths = Links.rest;
    State.linkBroken = Links.broken;
    LinkStateStale = false;
  }
  return State;
}

void PbdSimulation::checkDivergence() const
{
  ScopedStageTimer timer(Plan, Stage::DivergenceCheck);
  const bool finite = parallelReduce(
    State.positions.size(), 4096, true,
    [&](std::size_t i) { return State.positions[i].allFinite() && State.velocities[i].allFinite(); },
    [](bool a, bool b) { return a && b; });
  if (!finite)
  {
    std::ostringstream message;
    message << "The simulation blew up at t = " << State.time << " s (step " << State.stepCount
            << "): the state became non-finite. Check the compliances and the time step.";
    throw SimulationDivergedError(message.str(), State.time);
  }
}

AdvanceStatus PbdSimulation::advance(double endTime, const ProgressCallback& progress)
{
  if (Settings.stepControl == StepControl::ErrorControlled)
  {
    return advanceWithErrorControl(endTime, progress);
  }
  // The convergence of the last step is what a frame reports; no other step computes it
  // unless a tolerance asks for the residual every iteration.
  const bool report = Settings.reportConvergence;
  const auto stepAt = [&](double h, bool last) { stepOnce(h, report && last); };
  return advanceInEqualSteps(
    State, Step, endTime, progress, oneStepAtATime(stepAt), [&] { checkDivergence(); });
}

std::vector<double> PbdSimulation::tetVolumeRatios() const
{
  return softbody::tetVolumeRatios(Volumes.tets, Volumes.restVolume, State.positions, VolumeSlot);
}

TetStressField PbdSimulation::stressField() const
{
  return TetElastic.size() > 0 ? tetStressField(ElasticTopology, ElasticConstants, State.positions) : TetStressField{};
}

double PbdSimulation::elasticEnergy() const
{
  return TetElastic.size() > 0 ? tetElasticEnergy(ElasticTopology, ElasticConstants, State.positions)
                               : Simulation::elasticEnergy();
}

std::size_t PbdSimulation::brokenLinkCount() const
{
  return static_cast<std::size_t>(std::count(Links.broken.begin(), Links.broken.end(), 1));
}

std::size_t PbdSimulation::colorCount() const
{
  return LinkSchedule.coloring.colorCount();
}

} // namespace softbody
