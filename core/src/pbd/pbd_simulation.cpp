#include "softbody/pbd/pbd_simulation.h"

#include "softbody/common/errors.h"
#include "softbody/material/mass.h"
#include "softbody/material/material.h"
#include "softbody/common/parallel.h"
#include "softbody/common/stepping.h"
#include "softbody/mesh/topology.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>

namespace softbody
{
namespace
{

constexpr unsigned long long kDivergenceCheckInterval = 16;

void validateSettings(const PbdSettings& s)
{
  auto fail = [](const std::string& message) { throw InvalidInputError(message); };
  if (!(s.timeStep >= 0.0) || !std::isfinite(s.timeStep))
  {
    fail("TimeStep must be 0 (automatic) or a positive number of seconds.");
  }
  if (s.substeps < 1 || s.iterations < 1)
  {
    fail("Substeps and Iterations must be at least 1.");
  }
  if (!(s.residualTolerance >= 0.0) || !std::isfinite(s.residualTolerance))
  {
    fail("ResidualTolerance must be 0 (fixed iteration count) or positive.");
  }
  if (!(s.relaxation > 0.0 && s.relaxation < 2.0))
  {
    fail("Relaxation must lie in (0, 2); 1 is plain Gauss-Seidel or Jacobi.");
  }
  if (!s.gravity.allFinite() || !(s.damping >= 0.0) || !std::isfinite(s.damping))
  {
    fail("Gravity must be finite and Damping a non-negative rate [1/s].");
  }
  if (s.floorEnabled && (!(s.floor.normal.norm() > 0.0) || !s.floor.normal.allFinite() ||
                          !s.floor.origin.allFinite()))
  {
    fail("FloorNormal must be a nonzero finite vector and FloorOrigin finite.");
  }
  if (!(s.particleRadius >= 0.0) || !(s.friction >= 0.0) || !std::isfinite(s.friction) ||
    !(s.restitution >= 0.0 && s.restitution <= 1.0))
  {
    fail("ParticleRadius and Friction must be non-negative and Restitution in [0, 1].");
  }
  for (const ConstraintMaterial* m : { &s.links, &s.volumes, &s.attachments })
  {
    if (!(m->stiffness >= 0.0 && m->stiffness <= 1.0))
    {
      fail("PBD stiffnesses must lie in [0, 1].");
    }
    if (!(m->compliance >= 0.0) || !std::isfinite(m->compliance))
    {
      fail("XPBD compliances must be non-negative and finite.");
    }
  }
  if (!(s.breakingStrain >= 0.0) || !(s.plasticYield >= 0.0) || !(s.plasticCreep >= 0.0) ||
    !std::isfinite(s.breakingStrain + s.plasticYield + s.plasticCreep))
  {
    fail("BreakingStrain, PlasticYield and PlasticCreep must be non-negative (0 = off).");
  }
}

bool hardAttachment(const PbdSettings& s)
{
  return s.formulation == PbdFormulation::Pbd ? s.attachments.stiffness >= 1.0
                                              : s.attachments.compliance == 0.0;
}

const char* solverName(PbdSolver solver, double relaxation)
{
  switch (solver)
  {
    case PbdSolver::Jacobi:
      return "Jacobi";
    case PbdSolver::ParallelGaussSeidel:
      return "parallel Gauss-Seidel";
    case PbdSolver::GaussSeidel:
      break;
  }
  return relaxation == 1.0 ? "Gauss-Seidel" : "SOR";
}
} // namespace

PbdSimulation::PbdSimulation(PbdBody body, const PbdSettings& settings)
  : Settings(settings)
  , StageSeconds(kStageCount, 0.0)
{
  validateSettings(Settings);
  Settings.floor.normal.normalize();
  const std::size_t n = body.points.size();
  if (n == 0)
  {
    throw InvalidInputError("The input has no points.");
  }
  if (body.tets.empty() && body.links.empty())
  {
    throw InvalidInputError("PBD needs tetrahedra or line cells (links) to hold the particles "
                            "together; the input has neither.");
  }
  for (const Vec3& p : body.points)
  {
    if (!p.allFinite())
    {
      throw InvalidInputError("The input has points with NaN or infinite coordinates.");
    }
  }

  // Tets: the same validation as mass-spring (degenerate refused, inverted re-oriented or
  // refused by policy).
  Topology topology;
  if (!body.tets.empty())
  {
    TetMesh mesh{ body.points, std::move(body.tets) };
    std::vector<std::string> meshWarnings;
    mesh = prepareTetMesh(std::move(mesh), Settings.invertedTets, meshWarnings);
    for (const std::string& w : meshWarnings)
    {
      // Points outside every tet are expected here when links hold them.
      if (body.links.empty() || w.find("belong to no") == std::string::npos)
      {
        Warnings.push_back(w);
      }
    }
    topology = buildTopology(n, std::move(mesh.tets));
  }

  // Distance links: tet edges first, then the explicit links in input order.
  for (const Edge& e : topology.edges)
  {
    Links.ends.push_back({ e.a, e.b });
  }
  ExplicitLinkOffset = Links.ends.size();
  if (!body.linkStiffnessScale.empty() && body.linkStiffnessScale.size() != body.links.size())
  {
    throw InvalidInputError("The link stiffness array must have one value per link.");
  }
  for (std::size_t j = 0; j < body.links.size(); ++j)
  {
    const auto& l = body.links[j];
    if (l[0] < 0 || l[1] < 0 || std::size_t(l[0]) >= n || std::size_t(l[1]) >= n || l[0] == l[1])
    {
      throw InvalidInputError("Link " + std::to_string(j) + " refers to a missing point or links a point to itself.");
    }
    Links.ends.push_back(l);
  }
  Links.stiffnessScale.assign(Links.ends.size(), 1.0);
  for (std::size_t j = 0; j < body.linkStiffnessScale.size(); ++j)
  {
    const double scale = body.linkStiffnessScale[j];
    if (!(scale > 0.0) || !std::isfinite(scale))
    {
      throw InvalidInputError("Link stiffness factors must be positive; link " + std::to_string(j) + " has " + std::to_string(scale) + ".");
    }
    Links.stiffnessScale[ExplicitLinkOffset + j] = scale;
  }
  for (const auto& e : Links.ends)
  {
    const double length = (body.points[e[0]] - body.points[e[1]]).norm();
    if (!(length > 0.0))
    {
      throw InvalidInputError("A link joins two coincident points (zero rest length); merge them first.");
    }
    Links.originalRest.push_back(length);
  }
  Links.rest = Links.originalRest;
  Links.broken.assign(Links.size(), 0);
  Links.lambda.assign(Links.size(), 0.0);

  Volumes.tets = topology.tets;
  for (const Tet& t : Volumes.tets)
  {
    Volumes.restVolume.push_back(
      signedTetVolume(body.points[t[0]], body.points[t[1]], body.points[t[2]], body.points[t[3]]));
  }
  Volumes.broken.assign(Volumes.size(), 0);
  Volumes.lambda.assign(Volumes.size(), 0.0);
  if (Settings.elasticity.enabled && Settings.formulation == PbdFormulation::Xpbd && !Volumes.tets.empty())
  {
    setComplianceFromElasticity(topology, body.points);
  }

  // Masses: given per point, or density times the tet volumes.
  std::vector<double> mass;
  if (!body.pointMass.empty())
  {
    if (body.pointMass.size() != n)
    {
      throw InvalidInputError("The Mass array must have one value per point.");
    }
    for (double m : body.pointMass)
    {
      if (!(m > 0.0) || !std::isfinite(m))
      {
        throw InvalidInputError("Every point mass must be positive and finite.");
      }
    }
    mass = body.pointMass;
  }
  else
  {
    if (!(body.density > 0.0) || !std::isfinite(body.density))
    {
      throw InvalidInputError("Density must be positive.");
    }
    if (Volumes.tets.empty())
    {
      throw InvalidInputError("A body of links only needs a point array \"Mass\" (the Soft Body "
                              "Cloth and Voxelize sources write one).");
    }
    double volume = 0.0;
    for (double v : Volumes.restVolume)
    {
      volume += v;
    }
    const PointMasses distributed = distributeMass(topology, Volumes.restVolume,
      body.density * volume, body.massDistribution, 0.0, {});
    mass = distributed.mass;
    for (const auto& e : Links.ends)
    {
      if (mass[e[0]] <= 0.0 || mass[e[1]] <= 0.0)
      {
        throw InvalidInputError("Some linked points belong to no tet and so have no mass; give "
                                "the input a point array \"Mass\".");
      }
    }
  }

  // Pins: fixed points (w = 0) when hard, otherwise soft attachments to the rest position.
  const bool hardPins = hardAttachment(Settings);
  if (!body.pinned.empty() && body.pinned.size() != n)
  {
    throw InvalidInputError("The pinned-points array must have one value per point.");
  }
  InverseMass.assign(n, 0.0);
  Movable.assign(n, 1);
  for (std::size_t i = 0; i < n; ++i)
  {
    TotalMass += mass[i];
    const bool pinned = !body.pinned.empty() && body.pinned[i] != 0;
    if (mass[i] > 0.0 && !(pinned && hardPins))
    {
      InverseMass[i] = 1.0 / mass[i];
    }
    Movable[i] = InverseMass[i] > 0.0 ? 1 : 0;
    if (pinned && !hardPins)
    {
      Attachments.particle.push_back(static_cast<std::int32_t>(i));
      Attachments.target.push_back(body.points[i]);
    }
  }
  Attachments.lambda.assign(Attachments.size(), 0.0);

  // Only what the chosen solver uses: colors for parallel Gauss-Seidel, slots for Jacobi.
  if (Settings.solver != PbdSolver::GaussSeidel)
  {
    LinkSchedule = makeSchedule(Links, n, Movable);
    VolumeSchedule = makeSchedule(Volumes, n, Movable);
    AttachmentSchedule = makeSchedule(Attachments, n, Movable);
  }
  if (Settings.breakingStrain > 0.0)
  {
    TetEdges = topology.tetEdges;
  }
  if (Settings.solver == PbdSolver::ParallelGaussSeidel)
  {
    storeLinksAndVolumesByColor();
  }

  Rest = std::move(body.points);
  State.positions = Rest;
  State.velocities.assign(n, Vec3::Zero());
  if (Settings.breakingStrain > 0.0 || Settings.plasticYield > 0.0)
  {
    State.linkRestLengths = Links.rest;
    State.linkBroken = Links.broken;
  }
  Step = Settings.timeStep > 0.0 ? Settings.timeStep : kDefaultPbdStep;
  if (Settings.plasticYield > 0.0 && Settings.plasticCreep == 0.0)
  {
    Warnings.push_back("PlasticYield is set but PlasticCreep is 0, so links never flow.");
  }
}

void PbdSimulation::setComplianceFromElasticity(const Topology& topology, const std::vector<Vec3>& rest)
{
  MaterialSettings material;
  material.mode = MaterialMode::Physical;
  material.physical.youngsModulus = Settings.elasticity.youngsModulus;
  material.physical.poissonRatio = Settings.elasticity.poissonRatio;
  material.physical.dampingTime = 0.0;
  // The mass-spring constants are k / l0^2 [N/m] per edge and k_V / V0^2 per tet: exactly the
  // stiffness of C = l - l0 and C = V - V0, so the compliances are their inverses.
  const ElementConstants constants = computeElementConstants(topology, rest, material, Warnings);
  Links.compliance.assign(Links.size(), Settings.links.compliance);
  for (std::size_t e = 0; e < ExplicitLinkOffset; ++e)
  {
    Links.compliance[e] = 1.0 / constants.springStiffness[e];
  }
  Volumes.compliance.resize(Volumes.size());
  for (std::size_t t = 0; t < Volumes.size(); ++t)
  {
    const double k = constants.volumeStiffness[t];
    Volumes.compliance[t] = k > 0.0 ? 1.0 / k : std::numeric_limits<double>::infinity();
  }
}

void PbdSimulation::restoreState(const DynamicState& snapshot)
{
  if (snapshot.positions.size() != State.positions.size() ||
    snapshot.linkRestLengths.size() != State.linkRestLengths.size())
  {
    throw InvalidInputError("The snapshot does not belong to this simulation.");
  }
  State = snapshot;
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
}

void PbdSimulation::predict(double h)
{
  ScopedStageTimer timer(StageSeconds[kPredict]);
  const double keep = std::max(0.0, 1.0 - Settings.damping * h);
  const Vec3 g = Settings.gravity;
  const bool verlet = Settings.prediction == PbdPrediction::Verlet;
  Predicted.resize(State.positions.size());
  VelocityBefore.resize(State.positions.size());
  parallelFor(State.positions.size(), 1024, [&](std::size_t i) {
    const Vec3& x = State.positions[i];
    if (InverseMass[i] == 0.0)
    {
      Predicted[i] = x;
      VelocityBefore[i].setZero();
      return;
    }
    if (verlet)
    {
      // Position Verlet: the drift is the last step's displacement over h (stored as the
      // velocity), the acceleration enters as h^2 a.
      Predicted[i] = x + keep * h * State.velocities[i] + (h * h) * g;
      VelocityBefore[i] = (Predicted[i] - x) / h;
    }
    else
    {
      const Vec3 v = keep * (State.velocities[i] + h * g);
      VelocityBefore[i] = v;
      Predicted[i] = x + h * v;
    }
  });
  std::fill(Links.lambda.begin(), Links.lambda.end(), 0.0);
  std::fill(Volumes.lambda.begin(), Volumes.lambda.end(), 0.0);
  std::fill(Attachments.lambda.begin(), Attachments.lambda.end(), 0.0);
}

void PbdSimulation::sweep()
{
  std::vector<Vec3>& x = Predicted;
  const std::vector<double>& w = InverseMass;
  switch (Settings.solver)
  {
    case PbdSolver::GaussSeidel:
      gaussSeidelSweep(Links, x, w);
      gaussSeidelSweep(Volumes, x, w);
      gaussSeidelSweep(Attachments, x, w);
      break;
    case PbdSolver::ParallelGaussSeidel:
      coloredGaussSeidelSweep(Links, LinkSchedule, x, w);
      coloredGaussSeidelSweep(Volumes, VolumeSchedule, x, w);
      coloredGaussSeidelSweep(Attachments, AttachmentSchedule, x, w);
      break;
    case PbdSolver::Jacobi:
      jacobiSweep(Links, LinkSchedule, Settings.relaxation, x, w, JacobiScratch);
      jacobiSweep(Volumes, VolumeSchedule, Settings.relaxation, x, w, JacobiScratch);
      jacobiSweep(Attachments, AttachmentSchedule, Settings.relaxation, x, w, JacobiScratch);
      break;
  }
  if (Settings.floorEnabled)
  {
    projectFloor();
  }
}

double PbdSimulation::residual() const
{
  ScopedStageTimer timer(StageSeconds[kResidual]);
  const std::vector<Vec3>& x = Predicted;
  double sum = squaredResidual(Links, x, InverseMass) + squaredResidual(Volumes, x, InverseMass) +
    squaredResidual(Attachments, x, InverseMass);
  if (Settings.floorEnabled)
  {
    for (std::size_t i = 0; i < x.size(); ++i)
    {
      const double C = Settings.floor.normal.dot(x[i] - Settings.floor.origin) - Settings.particleRadius;
      if (C < 0.0 && InverseMass[i] > 0.0)
      {
        sum += C * C;
      }
    }
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
    {
      ScopedStageTimer timer(StageSeconds[kSolve]);
      sweep();
    }
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
}

void PbdSimulation::updateVelocities(double h)
{
  ScopedStageTimer timer(StageSeconds[kVelocities]);
  parallelFor(State.positions.size(), 1024, [&](std::size_t i) {
    State.velocities[i] = (Predicted[i] - State.positions[i]) / h;
    State.positions[i] = Predicted[i];
  });
}

void PbdSimulation::substep(double h, bool recordResiduals)
{
  prepareParameters(h);
  predict(h);
  if (Settings.floorEnabled)
  {
    InContact.assign(State.positions.size(), 0);
  }
  solve(recordResiduals);
  updateVelocities(h);
  if (Settings.floorEnabled && (Settings.friction > 0.0 || Settings.restitution > 0.0))
  {
    applyContactResponse(h);
  }
  if (Settings.breakingStrain > 0.0 || Settings.plasticYield > 0.0)
  {
    updateLinks(h);
  }
}

void PbdSimulation::step(double h)
{
  const double hs = h / Settings.substeps;
  for (int s = 0; s < Settings.substeps; ++s)
  {
    substep(hs, RecordEveryStep || s + 1 == Settings.substeps);
  }
  State.time += h;
  ++State.stepCount;
  if (!State.linkRestLengths.empty())
  {
    State.linkRestLengths = Links.rest;
    State.linkBroken = Links.broken;
  }
}

void PbdSimulation::checkDivergence() const
{
  ScopedStageTimer timer(StageSeconds[kDivergenceCheck]);
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
  const bool recordAll = RecordEveryStep;
  const AdvanceStatus status = advanceInEqualSteps(State, Step, endTime, progress,
    kDivergenceCheckInterval,
    [&](double h, bool last) {
      // The convergence of the last step is what a frame reports.
      RecordEveryStep = recordAll || last;
      step(h);
    },
    [&] { checkDivergence(); });
  RecordEveryStep = recordAll;
  return status;
}

std::vector<double> PbdSimulation::tetVolumeRatios() const
{
  std::vector<double> ratios(Volumes.size());
  const std::vector<Vec3>& x = State.positions;
  for (std::size_t t = 0; t < Volumes.size(); ++t)
  {
    const std::size_t s = VolumeSlot.empty() ? t : static_cast<std::size_t>(VolumeSlot[t]);
    const Tet& k = Volumes.tets[s];
    ratios[t] = signedTetVolume(x[k[0]], x[k[1]], x[k[2]], x[k[3]]) / Volumes.restVolume[s];
  }
  return ratios;
}

std::size_t PbdSimulation::brokenLinkCount() const
{
  return static_cast<std::size_t>(std::count(Links.broken.begin(), Links.broken.end(), 1));
}

std::size_t PbdSimulation::colorCount() const
{
  return LinkSchedule.coloring.colorCount();
}

std::vector<StageTiming> PbdSimulation::stageTimings() const
{
  std::vector<StageTiming> timings;
  const char* prediction =
    Settings.prediction == PbdPrediction::Verlet ? "predict: Verlet" : "predict: symplectic Euler";
  timings.push_back({ prediction, StageSeconds[kPredict] });
  std::ostringstream solve;
  solve << (Settings.formulation == PbdFormulation::Xpbd ? "XPBD " : "PBD ")
        << solverName(Settings.solver, Settings.relaxation) << ": links";
  if (!Volumes.tets.empty())
  {
    solve << " + volumes";
  }
  if (Attachments.size() > 0)
  {
    solve << " + attachments";
  }
  if (Settings.floorEnabled)
  {
    solve << " + floor";
  }
  timings.push_back({ solve.str(), StageSeconds[kSolve] });
  timings.push_back({ "residual", StageSeconds[kResidual] });
  timings.push_back({ "velocity update", StageSeconds[kVelocities] });
  if (Settings.floorEnabled && (Settings.friction > 0.0 || Settings.restitution > 0.0))
  {
    timings.push_back({ "contact friction + restitution", StageSeconds[kContacts] });
  }
  if (Settings.breakingStrain > 0.0 || Settings.plasticYield > 0.0)
  {
    timings.push_back({ "links: plasticity + breaking", StageSeconds[kLinks] });
  }
  timings.push_back({ "divergence check", StageSeconds[kDivergenceCheck] });
  return timings;
}

} // namespace softbody
