// PBD/XPBD set-up: validation, the constraint batches, masses and pins, the solver's schedules
// and the step plan. The stepping itself is in pbd_simulation.cpp.
#include "softbody/pbd/pbd_simulation.h"

#include "softbody/common/errors.h"
#include "softbody/common/validation.h"
#include "softbody/material/constraint_forms.h"
#include "softbody/material/mass.h"
#include "softbody/material/material.h"
#include "softbody/material/tet_elasticity.h"
#include "softbody/mesh/reorder.h"
#include "softbody/mesh/tet_mesh.h"
#include "softbody/pbd/pbd_plan.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <string>

namespace softbody
{
namespace
{

/// Whether the tets' constraints come from the body's material (XPBD: a continuum model always,
/// the Spring Network when asked) rather than from the constraint types' compliances.
bool constraintsFromMaterial(const PbdSettings& s, const MaterialSettings& material)
{
  return s.formulation == PbdFormulation::Xpbd && (s.elasticFromMaterial || isContinuum(material.model));
}

/// What the body's material may ask of this formulation, refused with the reason and the
/// pairing that works. Its values are checked cell by cell where the constants are computed
/// (validateMaterial), as under Mass-Spring.
void validateMaterialUse(const PbdSettings& s, const Body& body)
{
  const MaterialSettings& material = body.material;
  const std::string name = materialModelName(material.model);
  if (material.mode != MaterialMode::Physical)
  {
    throw InvalidInputError("PBD and XPBD read a Physical material (density, and under XPBD Young's "
                            "modulus and Poisson's ratio); MaterialMode Raw is Mass-Spring's.");
  }
  if (isContinuum(material.model) && s.formulation != PbdFormulation::Xpbd)
  {
    throw InvalidInputError("MaterialModel " + name + " needs XPBD: its constraints' compliances "
      "come from Young's modulus, and PBD's stiffnesses in [0, 1] have no modulus. Use XPBD, or "
      "MaterialModel Spring Network with PBD's stiffnesses.");
  }
  const CellMaterial& cells = material.cells;
  if (!constraintsFromMaterial(s, material))
  {
    if (!cells.youngsModulus.empty() || !cells.poissonRatio.empty())
    {
      throw InvalidInputError("Per-cell Young's moduli and Poisson's ratios set the tets' "
        "constraints only when XPBD takes them from the material (XPBDMaterial Young's modulus, or "
        "a continuum MaterialModel); with PBD's stiffnesses or XPBD's compliances they would be "
        "ignored. Remove them (YoungsModulusArray and PoissonRatioArray None), or use XPBD with "
        "XPBDMaterial Young's modulus.");
    }
  }
  else
  {
    const PhysicalMaterial& m = material.physical;
    check::positive("YoungsModulus", m.youngsModulus, "Pa");
    if (isContinuum(material.model))
    {
      check::inRange("PoissonRatio", m.poissonRatio, -1.0, 0.5, true, true);
    }
    else
    {
      check::inRange("PoissonRatio", m.poissonRatio, 0.0, 0.5, false, true);
    }
  }
  if (!cells.density.empty() && !body.pointMass.empty())
  {
    throw InvalidInputError("The body has both point masses (a \"Mass\" point array) and per-cell "
      "densities; the masses would ignore the densities. Remove one of them.");
  }
  if (isContinuum(material.model) && (s.breakingStrain > 0.0 || s.plasticYield > 0.0))
  {
    std::ostringstream message;
    message << "BreakingStrain " << s.breakingStrain << " and PlasticYield " << s.plasticYield
            << " act on links, and MaterialModel " << name << " holds its tets by their "
            << "deformation, not by links along their edges. Set both to 0, or use MaterialModel "
            << "Spring Network.";
    throw InvalidInputError(message.str());
  }
}

/// The hydrostatic constraint's compliance is 1 / (kH V0); kH < 0 (Corotated's lambda below
/// nu = 0, Stable Neo-Hookean's lambda - mu / 4 below nu = -0.5) is no compliance. Refused
/// quoting the Poisson's ratio, and the cell when it is a per-cell value.
void refuseNegativeHydrostaticStiffness(MaterialModel model, double poissonRatio, const std::string& where)
{
  std::ostringstream message;
  message << "PoissonRatio " << poissonRatio << where << " gives " << materialModelName(model)
          << "'s hydrostatic constraint a negative stiffness, which XPBD cannot take as a "
          << "compliance. Under XPBD Corotated needs PoissonRatio in [0, 0.5) and Stable "
          << "Neo-Hookean in [-0.5, 0.5); Method Mass-Spring runs both at any PoissonRatio in "
          << "(-1, 0.5).";
  throw InvalidInputError(message.str());
}

void validateSettings(const PbdSettings& s)
{
  check::nonNegative("TimeStep", s.timeStep, "s", "automatic");
  check::atLeast("Substeps", s.substeps, 1);
  check::atLeast("Iterations", s.iterations, 1);
  check::nonNegative("ResidualTolerance", s.residualTolerance, "", "run every iteration");
  check::inRange("Relaxation", s.relaxation, 0.0, 2.0, true, true);
  validateScene(s);
  if (s.stepControl == StepControl::ErrorControlled && s.formulation == PbdFormulation::Pbd)
  {
    // PBD's stiffness depends on the step and the iteration count, so shorter steps make a
    // stiffer body: there is no one motion for the steps to converge to.
    throw InvalidInputError("TimeStepMode 1 (Error-controlled) needs a motion that shorter steps "
                            "converge to, and PBD's stiffnesses change with the step and the "
                            "iterations. Set Method to XPBD (compliances in SI units) or "
                            "Mass-Spring, or TimeStepMode to 0 (Fixed).");
  }
  check::nonNegative("VelocityDamping", s.damping, "1/s", "undamped");
  check::nonNegative("ParticleRadius", s.particleRadius, "m");
  check::nonNegative("StaticFriction", s.collisions.staticFriction, "", "frictionless");
  check::nonNegative("DynamicFriction", s.collisions.dynamicFriction, "", "frictionless");
  check::inRange("Restitution", s.collisions.restitution, 0.0, 1.0);
  check::nonNegative("CollisionMargin", s.collisions.margin, "m", "automatic");
  check::inRange("PBDLinkStiffness", s.links.stiffness, 0.0, 1.0);
  check::inRange("PBDVolumeStiffness", s.volumes.stiffness, 0.0, 1.0);
  check::inRange("PBDPinStiffness", s.attachments.stiffness, 0.0, 1.0);
  check::nonNegative("XPBDLinkCompliance", s.links.compliance, "m/N", "rigid");
  check::nonNegative("XPBDVolumeCompliance", s.volumes.compliance, "m^3/Pa", "rigid");
  check::nonNegative("XPBDPinCompliance", s.attachments.compliance, "m/N", "rigid");
  check::nonNegative("BreakingStrain", s.breakingStrain, "", "unbreakable");
  check::nonNegative("PlasticYield", s.plasticYield, "", "elastic");
  check::nonNegative("PlasticCreep", s.plasticCreep, "1/s");
}

bool hardAttachment(const PbdSettings& s)
{
  return s.formulation == PbdFormulation::Pbd ? s.attachments.stiffness >= 1.0
                                              : s.attachments.compliance == 0.0;
}

} // namespace

PbdSimulation::PbdSimulation(Body body, const PbdSettings& settings)
  : Settings(settings)
{
  validateSettings(Settings);
  validateMaterialUse(Settings, body);
  Settings.floor.normal.normalize();
  const std::size_t n = body.mesh.points.size();
  if (n == 0)
  {
    throw InvalidInputError("The input has no points.");
  }
  if (body.mesh.tets.empty() && body.links.empty())
  {
    throw InvalidInputError("PBD needs tetrahedra or line cells (links) to hold the particles "
                            "together; the input has neither.");
  }
  for (const Vec3& p : body.mesh.points)
  {
    if (!p.allFinite())
    {
      throw InvalidInputError("The input has points with NaN or infinite coordinates.");
    }
  }
  if (Settings.stepControl == StepControl::ErrorControlled)
  {
    if (const std::string problem = errorToleranceProblem(Settings.errorTolerance, body.mesh.points); !problem.empty())
    {
      throw InvalidInputError(problem);
    }
  }

  // Tets: the same validation as mass-spring (degenerate refused, inverted re-oriented or
  // refused by policy).
  Topology topology;
  if (!body.mesh.tets.empty())
  {
    TetMesh mesh{ body.mesh.points, std::move(body.mesh.tets) };
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

  // Distance links: tet edges first (the spring network's; a continuum model holds its tets by
  // their deformation instead), then the explicit links in input order.
  const bool fromMaterial = constraintsFromMaterial(Settings, body.material);
  const bool continuum = fromMaterial && isContinuum(body.material.model);
  if (!continuum)
  {
    for (const Edge& e : topology.edges)
    {
      Links.ends.push_back({ e.a, e.b });
    }
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
    const double length = (body.mesh.points[e[0]] - body.mesh.points[e[1]]).norm();
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
      signedTetVolume(body.mesh.points[t[0]], body.mesh.points[t[1]], body.mesh.points[t[2]], body.mesh.points[t[3]]));
  }
  Volumes.broken.assign(Volumes.size(), 0);
  Volumes.lambda.assign(Volumes.size(), 0.0);
  if (continuum && !Volumes.tets.empty())
  {
    setUpTetElasticity(topology, body.mesh.points, body.material);
  }
  else if (fromMaterial && !Volumes.tets.empty())
  {
    setComplianceFromElasticity(topology, body.mesh.points, body.material);
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
    check::positive("Density", body.material.physical.density, "kg/m^3");
    if (Volumes.tets.empty())
    {
      throw InvalidInputError("A body of links only needs a point array \"Mass\" (the Soft Body "
                              "Cloth and Voxelize sources write one).");
    }
    // Each tet's mass (rho_t V_t) is spread over its points, as under Mass-Spring; with a
    // uniform density that is the rest volume in proportion.
    std::vector<double> cellMasses;
    double totalMass = 0.0;
    if (body.material.cells.density.empty())
    {
      for (double v : Volumes.restVolume)
      {
        totalMass += v;
      }
      totalMass *= body.material.physical.density;
    }
    else
    {
      validateCells(body.material, Volumes.size(), Warnings);
      cellMasses = tetMasses(body.material, Volumes.restVolume);
      for (double m : cellMasses)
      {
        totalMass += m;
      }
    }
    const PointMasses distributed = distributeMass(topology,
      cellMasses.empty() ? Volumes.restVolume : cellMasses, totalMass,
      body.material.massDistribution, 0.0, {});
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
  double bodyMass = 0.0;
  for (double m : mass)
  {
    bodyMass += m;
  }
  // Points whose x, y and z a condition holds are kinematic (inverse mass 0), moved each
  // substep to where the condition puts them.
  Conditions = BoundaryConditions(std::move(body.conditions), body.mesh.points, topology.tets, bodyMass, Warnings);
  Conditions.setMasses(mass);
  PointMass = mass; // held points keep their mass for the reactions (their inverse mass is 0)
  const std::vector<char> held = Conditions.fullyHeld();
  InverseMass.assign(n, 0.0);
  Movable.assign(n, 1);
  for (std::size_t i = 0; i < n; ++i)
  {
    TotalMass += mass[i];
    const bool pinned = !body.pinned.empty() && body.pinned[i] != 0;
    if (mass[i] > 0.0 && !(pinned && hardPins) && !held[i])
    {
      InverseMass[i] = 1.0 / mass[i];
    }
    Movable[i] = InverseMass[i] > 0.0 ? 1 : 0;
    if (pinned && !hardPins)
    {
      Attachments.particle.push_back(static_cast<std::int32_t>(i));
      Attachments.target.push_back(body.mesh.points[i]);
    }
  }
  Attachments.lambda.assign(Attachments.size(), 0.0);

  if (Settings.breakingStrain > 0.0)
  {
    TetEdges = topology.tetEdges;
  }
  // Tets sorted by their vertices, so a sweep visits neighbouring tets one after the other
  // (the tet edges already are: topology sorts them by their ends). With vertices numbered
  // along a space-filling curve (mesh/reorder.h) this is what keeps a sweep in cache.
  if (Volumes.size() > 1)
  {
    storeVolumesInOrder(tetOrderByVertices(Volumes.tets, {}));
  }

  // Only what the chosen solver uses: colors for parallel Gauss-Seidel, slots for Jacobi.
  if (Settings.solver != PbdSolver::GaussSeidel)
  {
    LinkSchedule = makeSchedule(Links, n, Movable);
    VolumeSchedule = makeSchedule(Volumes, n, Movable);
    AttachmentSchedule = makeSchedule(Attachments, n, Movable);
  }
  if (Settings.solver == PbdSolver::ParallelGaussSeidel)
  {
    storeLinksAndVolumesByColor();
  }
  else if (Settings.solver == PbdSolver::GaussSeidel)
  {
    storeLinksAndVolumesInStreams();
  }

  Rest = std::move(body.mesh.points);
  State.positions = Rest;
  State.velocities.assign(n, Vec3::Zero());
  Conditions.holdPoints(0.0, State.positions, State.velocities);
  labelBodies();
  setUpCollisions(topology.tets, body.surfaceTriangles);
  replan();
  if (!Conditions.heldAxes().empty() && !constraintsHaveForces())
  {
    // Each Gauss-Seidel projection moves its corners by w_k dC/dx_k dLambda: the momentum it
    // gives them is dC/dx_k dLambda / h, so the multipliers tell what the held points were
    // given. Averaged Jacobi moves a point by the mean of the corrections asked of it instead.
    ReactionsFromMultipliers = Settings.solver != PbdSolver::Jacobi;
    if (!ReactionsFromMultipliers)
    {
      Warnings.push_back("The supports' reactions are not reported (no Reaction output): "
                         "Solver Jacobi moves a point by the mean of the corrections asked of "
                         "it, so its multipliers are not the momentum the supports gave. Solver "
                         "Gauss-Seidel or Parallel Gauss-Seidel reports them.");
    }
  }
  // Rest lengths and broken flags are state (snapshotted, restored) only where they change.
  if (Plan.runs(Stage::UpdateLinks))
  {
    State.linkRestLengths = Links.rest;
    State.linkBroken = Links.broken;
  }
  if (Plan.runs(Stage::CollisionDetect) && Settings.floorActive())
  {
    liftBodiesOntoFloor();
  }
  Step = Settings.timeStep > 0.0 ? Settings.timeStep : kDefaultPbdStep;
  if (Settings.plasticYield > 0.0 && Settings.plasticCreep == 0.0)
  {
    Warnings.push_back("PlasticYield is set but PlasticCreep is 0, so links never flow.");
  }
}

void PbdSimulation::labelBodies()
{
  // Union-find over the links (tet edges included): a body is a connected component.
  const std::size_t n = Rest.size();
  std::vector<std::int32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  const auto root = [&](std::int32_t i) {
    while (parent[i] != i)
    {
      parent[i] = parent[parent[i]];
      i = parent[i];
    }
    return i;
  };
  const auto join = [&](std::int32_t i, std::int32_t j) {
    const std::int32_t a = root(i), b = root(j);
    if (a != b)
    {
      parent[std::max(a, b)] = std::min(a, b); // the root is the body's lowest index
    }
  };
  for (const auto& e : Links.ends)
  {
    join(e[0], e[1]);
  }
  // A continuum body's tets have no edge links.
  for (const Tet& t : TetElastic.tets)
  {
    join(t[0], t[1]);
    join(t[0], t[2]);
    join(t[0], t[3]);
  }
  BodyOf.assign(n, -1);
  BodyFirstPoint.clear();
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::int32_t r = root(static_cast<std::int32_t>(i));
    if (BodyOf[r] < 0)
    {
      BodyOf[r] = static_cast<std::int32_t>(BodyFirstPoint.size());
      BodyFirstPoint.push_back(r);
    }
    BodyOf[i] = BodyOf[r];
  }
}

void PbdSimulation::setUpTetElasticity(
  const Topology& topology, const std::vector<Vec3>& rest, const MaterialSettings& bodyMaterial)
{
  if (bodyMaterial.volumetric == VolumetricFormulation::NodalAverage)
  {
    throw InvalidInputError("VolumetricFormulation Nodal Average is for the Mass-Spring method's "
      "Newton and explicit solvers: XPBD's tet constraints are each tet's own. Use VolumetricFormulation "
      "Per Tet with XPBD, or Method Mass-Spring with Implicit Euler, BDF2, Static or an explicit integrator.");
  }
  MaterialSettings material = bodyMaterial;
  material.physical.dampingTime = 0.0; // XPBD damps through VelocityDamping
  ElasticTopology = topology;
  ElasticConstants = computeTetElasticConstants(topology, rest, material, Warnings);
  ElasticConstants.damped = false;
  const std::size_t tetCount = topology.tets.size();
  TetElastic.model = material.model;
  TetElastic.tets = topology.tets;
  TetElastic.shapeGradients = ElasticConstants.shapeGradients;
  TetElastic.restJ.resize(tetCount);
  TetElastic.deviatoricCompliance.resize(tetCount);
  TetElastic.hydrostaticCompliance.resize(tetCount);
  withElasticLaw(material.model, [&](auto law) {
    using Form = ConstraintForm<decltype(law)>;
    for (std::size_t t = 0; t < tetCount; ++t)
    {
      const LameParameters& p = ElasticConstants.law[t];
      const double volume = ElasticConstants.restVolume[t];
      const double kH = Form::hydrostaticStiffness(p);
      if (kH < 0.0)
      {
        refuseNegativeHydrostaticStiffness(material.model, material.physicalOf(t).poissonRatio,
          material.cells.poissonRatio.empty() ? "" : " (cell " + std::to_string(t) + ")");
      }
      TetElastic.restJ[t] = Form::restJ(p);
      TetElastic.deviatoricCompliance[t] = 1.0 / (Form::deviatoricStiffness(p) * volume);
      TetElastic.hydrostaticCompliance[t] =
        kH > 0.0 ? 1.0 / (kH * volume) : std::numeric_limits<double>::infinity();
    }
  });
  TetElastic.lambda.assign(tetCount, TetElasticMultipliers::Zero());
  // The volume batch keeps the tets' rest volumes and order for the held-tet repair and the
  // volume ratios, with no stiffness of its own; explicit links keep their compliance.
  Links.compliance.assign(Links.size(), Settings.links.compliance);
  Volumes.compliance.assign(Volumes.size(), std::numeric_limits<double>::infinity());
}

void PbdSimulation::setComplianceFromElasticity(
  const Topology& topology, const std::vector<Vec3>& rest, const MaterialSettings& bodyMaterial)
{
  MaterialSettings material = bodyMaterial;
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

} // namespace softbody
