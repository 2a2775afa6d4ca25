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

void validateElasticity(const PbdSettings& s)
{
  check::positive("YoungsModulus", s.elasticity.youngsModulus, "Pa");
  const MaterialModel model = s.elasticity.model;
  const std::string name = materialModelName(model);
  if (!isContinuum(model))
  {
    check::inRange("PoissonRatio", s.elasticity.poissonRatio, 0.0, 0.5, false, true);
    return;
  }
  if (s.formulation != PbdFormulation::Xpbd)
  {
    throw InvalidInputError("MaterialModel " + name + " needs XPBD: its constraints' compliances "
      "come from Young's modulus, and PBD's stiffnesses in [0, 1] have no modulus. Use XPBD, or "
      "MaterialModel Spring Network with PBD's stiffnesses.");
  }
  check::inRange("PoissonRatio", s.elasticity.poissonRatio, -1.0, 0.5, true, true);
  // The hydrostatic constraint's compliance is 1 / (kH V0); kH < 0 (Corotated's lambda below
  // nu = 0, Stable Neo-Hookean's lambda - mu / 4 below nu = -0.5) is no compliance.
  const LameParameters linear = lameFromYoung(s.elasticity.youngsModulus, s.elasticity.poissonRatio);
  const double kH = withElasticLaw(model, [&](auto law) {
    using Law = decltype(law);
    return ConstraintForm<Law>::hydrostaticStiffness(Law::fromLinear(linear));
  });
  if (kH < 0.0)
  {
    std::ostringstream message;
    message << "PoissonRatio " << s.elasticity.poissonRatio << " gives " << name << "'s hydrostatic "
            << "constraint a negative stiffness, which XPBD cannot take as a compliance. Under XPBD "
            << "Corotated needs PoissonRatio in [0, 0.5) and Stable Neo-Hookean in [-0.5, 0.5); "
            << "Method Mass-Spring runs both at any PoissonRatio in (-1, 0.5).";
    throw InvalidInputError(message.str());
  }
  if (s.breakingStrain > 0.0 || s.plasticYield > 0.0)
  {
    std::ostringstream message;
    message << "BreakingStrain " << s.breakingStrain << " and PlasticYield " << s.plasticYield
            << " act on links, and MaterialModel " << name << " holds its tets by their "
            << "deformation, not by links along their edges. Set both to 0, or use MaterialModel "
            << "Spring Network.";
    throw InvalidInputError(message.str());
  }
}

void validateSettings(const PbdSettings& s)
{
  check::nonNegative("TimeStep", s.timeStep, "s", "automatic");
  check::atLeast("Substeps", s.substeps, 1);
  check::atLeast("Iterations", s.iterations, 1);
  check::nonNegative("ResidualTolerance", s.residualTolerance, "", "run every iteration");
  check::inRange("Relaxation", s.relaxation, 0.0, 2.0, true, true);
  validateScene(s);
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
  if (s.elasticity.enabled)
  {
    validateElasticity(s);
  }
}

bool hardAttachment(const PbdSettings& s)
{
  return s.formulation == PbdFormulation::Pbd ? s.attachments.stiffness >= 1.0
                                              : s.attachments.compliance == 0.0;
}

} // namespace

PbdSimulation::PbdSimulation(PbdBody body, const PbdSettings& settings)
  : Settings(settings)
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

  // Distance links: tet edges first (the spring network's; a continuum model holds its tets by
  // their deformation instead), then the explicit links in input order.
  const bool continuum = Settings.elasticity.enabled && isContinuum(Settings.elasticity.model);
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
  if (continuum && !Volumes.tets.empty())
  {
    setUpTetElasticity(topology, body.points);
  }
  else if (Settings.elasticity.enabled && Settings.formulation == PbdFormulation::Xpbd && !Volumes.tets.empty())
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
  double bodyMass = 0.0;
  for (double m : mass)
  {
    bodyMass += m;
  }
  // Points whose x, y and z a condition holds are kinematic (inverse mass 0), moved each
  // substep to where the condition puts them.
  Conditions = BoundaryConditions(std::move(body.conditions), body.points, topology.tets, bodyMass, Warnings);
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
      Attachments.target.push_back(body.points[i]);
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

  Rest = std::move(body.points);
  State.positions = Rest;
  State.velocities.assign(n, Vec3::Zero());
  Conditions.holdPoints(0.0, State.positions, State.velocities);
  labelBodies();
  setUpCollisions(topology.tets, body.surfaceTriangles);
  replan();
  if (!Conditions.heldAxes().empty() && !constraintsHaveForces())
  {
    std::ostringstream message;
    message << "The supports' reactions are not reported (no Reaction output): ";
    if (Settings.formulation == PbdFormulation::Pbd)
    {
      message << "PBD's stiffnesses in [0, 1] are no forces. XPBD reports them.";
    }
    else
    {
      message << "a constraint type is rigid (XPBDLinkCompliance " << Settings.links.compliance
              << " m/N, XPBDVolumeCompliance " << Settings.volumes.compliance
              << " m^3/Pa), and a rigid constraint has no force to report. Give it a compliance, "
                 "or XPBDMaterial Young's Modulus.";
    }
    Warnings.push_back(message.str());
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

void PbdSimulation::setUpTetElasticity(const Topology& topology, const std::vector<Vec3>& rest)
{
  MaterialSettings material;
  material.model = Settings.elasticity.model;
  material.mode = MaterialMode::Physical;
  material.physical.youngsModulus = Settings.elasticity.youngsModulus;
  material.physical.poissonRatio = Settings.elasticity.poissonRatio;
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
      TetElastic.restJ[t] = Form::restJ(p);
      TetElastic.deviatoricCompliance[t] = 1.0 / (Form::deviatoricStiffness(p) * volume);
      TetElastic.hydrostaticCompliance[t] = kH > 0.0 ? 1.0 / (kH * volume) : std::numeric_limits<double>::infinity();
    }
  });
  TetElastic.lambda.assign(tetCount, TetElasticMultipliers::Zero());
  // The volume batch keeps the tets' rest volumes and order for the held-tet repair and the
  // volume ratios, with no stiffness of its own; explicit links keep their compliance.
  Links.compliance.assign(Links.size(), Settings.links.compliance);
  Volumes.compliance.assign(Volumes.size(), std::numeric_limits<double>::infinity());
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

} // namespace softbody
