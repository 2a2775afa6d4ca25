#include "softbody/massspring/mass_spring_setup.h"

#include "softbody/collision/start_overlap.h"
#include "softbody/massspring/amg_preconditioner.h"
#include "softbody/massspring/tet_body_contacts.h"
#include "softbody/common/stepping.h"

#include "softbody/common/error_control.h"
#include "softbody/common/errors.h"
#include "softbody/common/validation.h"
#include "softbody/stability/element_frequency.h"
#include "softbody/stability/stability.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace softbody
{
namespace
{

void validateScene(const SceneSettings& scene)
{
  check::nonNegative("TimeStep", scene.timeStep, "s", "automatic");
  softbody::validateScene(scene);
  if (scene.strainLimit != 0.0 && !(scene.strainLimit > 1.0 && std::isfinite(scene.strainLimit)))
  {
    throw InvalidInputError("StrainLimit must be 0 (off) or a finite stretch factor > 1, got " +
      check::quote(scene.strainLimit) + ".");
  }
  check::atLeast("StrainLimitIterations", scene.strainLimitIterations, 1);
  check::inRange("stability safety factor", scene.stabilitySafety, 0.0, 1.0, true, false);
  if (isImplicit(scene.integrator))
  {
    check::nonNegative("ImplicitTolerance", scene.implicit.tolerance, "", "Projective Dynamics: "
      "a fixed iteration count");
    const bool newton = scene.integrator == Integrator::ImplicitEuler || scene.integrator == Integrator::Bdf2;
    if (newton && !(scene.implicit.tolerance > 0.0))
    {
      throw InvalidInputError(std::string("ImplicitTolerance must be > 0 for ") +
        integratorName(scene.integrator) + " (Newton stops on it), got " +
        check::quote(scene.implicit.tolerance) + ".");
    }
    check::atLeast("ImplicitMaxIterations", scene.implicit.maxIterations, 1);
    if (scene.implicit.preconditioner == LinearPreconditioner::AlgebraicMultigrid &&
      (newton || scene.integrator == Integrator::Static))
    {
      requireAlgebraicMultigrid();
    }
    check::inRange("Chebyshev radius of Vertex Block Descent", scene.implicit.chebyshevRadius, 0.0, 1.0, false, true);
  }
  if (scene.stepControl == StepControl::ErrorControlled && factsOf(scene.integrator).order < 1)
  {
    throw InvalidInputError(std::string("Error-controlled steps need an integrator whose answer depends on "
      "its step; ") + integratorName(scene.integrator) + " solves for the equilibrium at each frame time and "
      "has no time error: choose TimeStepMode Fixed, or a dynamic integrator.");
  }
}

/// Refuses an error tolerance the body's coordinates cannot resolve (error_control.h).
void validateErrorTolerance(const SceneSettings& scene, const TetMesh& mesh)
{
  if (scene.stepControl != StepControl::ErrorControlled)
  {
    return;
  }
  if (const std::string problem = errorToleranceProblem(scene.errorTolerance, mesh.points); !problem.empty())
  {
    throw InvalidInputError(problem);
  }
}

/// Step size from the stability estimate (auto mode) or the user's choice, with warnings.
void chooseStep(MassSpringSetup& s)
{
  const SceneSettings& scene = s.scene;
  const ElementConstants& c = s.constants;
  s.omegaMax = modelFrequencyBound(s.model, s.topology, c, s.tetConstants, s.masses.inverseMass, s.mesh.points);
  if (isImplicit(scene.integrator))
  {
    // Stable at any step: automatic means one step per advance() call (per frame in the
    // filter). No stability estimate applies.
    s.step = scene.timeStep > 0.0 ? scene.timeStep : std::numeric_limits<double>::infinity();
    s.stableStep = 0.0;
    s.undampedStableStep = 0.0;
    return;
  }
  s.stableStep = stableTimeStep(scene.integrator, s.omegaMax, c.minDampingTime, c.maxDampingTime);
  const double symplecticStep =
    stableTimeStep(Integrator::EulerCromer, s.omegaMax, c.minDampingTime, c.maxDampingTime);
  s.undampedStableStep =
    stableTimeStep(factsOf(scene.integrator).undampedReference, s.omegaMax, 0.0, 0.0);
  if (scene.timeStep > 0.0)
  {
    s.step = scene.timeStep;
    if (s.stableStep > 0.0 && s.step > s.stableStep)
    {
      std::ostringstream message;
      message << "TimeStep " << s.step << " s is above the estimated stable step " << s.stableStep
              << " s of " << integratorName(scene.integrator);
      if (scene.stepControl == StepControl::ErrorControlled)
      {
        message << "; error-controlled steps stay within " << scene.stabilitySafety * s.stableStep
                << " s instead.";
      }
      else
      {
        message << "; the simulation may blow up (set TimeStep to 0 for automatic).";
      }
      s.warnings.push_back(message.str());
    }
  }
  else if (s.stableStep > 0.0)
  {
    s.step = scene.stabilitySafety * s.stableStep;
  }
  else if (symplecticStep > 0.0)
  {
    // Explicit Euler without damping amplifies every oscillation at any step size.
    s.step = 0.1 * scene.stabilitySafety * symplecticStep;
    std::ostringstream message;
    message << integratorName(scene.integrator)
            << " has no stable step without damping: oscillations grow at any step. Using "
            << s.step << " s; add damping or choose Euler-Cromer or Verlet.";
    s.warnings.push_back(message.str());
  }
  else
  {
    s.step = 1e-3; // no internal stiffness at all (e.g. zero constants): any step is stable
  }
}

} // namespace

MassSpringSetup prepareMassSpring(Body body, const SceneSettings& scene)
{
  MassSpringSetup s;
  s.scene = scene;
  validateScene(s.scene);
  if (!body.pinned.empty() && body.pinned.size() != body.mesh.points.size())
  {
    throw InvalidInputError("The pinned-point flags do not match the number of points.");
  }
  if (const std::string parts = body.particleOnlyParts(); !parts.empty())
  {
    throw InvalidInputError("The body has " + parts + ", which only the particle engine (Method "
      "PBD or XPBD) reads; the mass-spring and finite-element methods take tets alone.");
  }
  if (body.material.volumetric == VolumetricFormulation::NodalAverage &&
    (scene.integrator == Integrator::ProjectiveDynamics || scene.integrator == Integrator::VertexBlockDescent))
  {
    throw InvalidInputError(std::string("VolumetricFormulation Nodal Average couples every point's tets through "
      "the point's volume, which ") + integratorName(scene.integrator) +
      " cannot hold (it solves element by element or point by point): use Implicit Euler, BDF2, Static "
      "or an explicit integrator, or VolumetricFormulation Per Tet.");
  }
  s.mesh = prepareTetMesh(std::move(body.mesh), s.scene.invertedTets, s.warnings);
  validateErrorTolerance(s.scene, s.mesh);
  if (s.scene.stepControl == StepControl::ErrorControlled && s.scene.floorActive())
  {
    // Measured on a TetGen sphere (27,792 tets) resting on the floor: 10,037 steps in its first
    // 0.1 s and 88 tets inverted, where fixed 1/240 s BDF2 steps invert none.
    s.warnings.push_back("Error-controlled steps with the floor: where the body touches it the "
      "steps get very short (thousands per frame) and can invert tets; for scenes with contact use "
      "TimeStepMode Fixed (BDF2 at a TimeStep that resolves the landing).");
  }
  s.topology = buildTopology(s.mesh.points.size(), s.mesh.tets);
  s.model = body.material.model;
  s.constants = computeElementConstants(s.topology, s.mesh.points, body.material, s.warnings);
  if (isContinuum(s.model))
  {
    std::vector<std::string> repeated; // the material's warnings are said once, above
    s.tetConstants =
      computeTetElasticConstants(s.topology, s.mesh.points, body.material, repeated);
  }

  // Each tet's mass (rho_t V_t) is spread over its points; with a uniform density that is the
  // rest volume in proportion, as it always was.
  double restVolume = 0.0;
  for (double v : s.constants.restVolume)
  {
    restVolume += v;
  }
  std::vector<double> cellMasses;
  double totalMass = 0.0;
  if (body.material.cells.density.empty())
  {
    totalMass = totalMassOf(body.material, restVolume);
  }
  else
  {
    cellMasses = tetMasses(body.material, s.constants.restVolume);
    for (double m : cellMasses)
    {
      totalMass += m;
    }
  }
  // Points whose x, y and z are all held move only as their conditions say: inverse mass 0,
  // like pins.
  s.conditions = BoundaryConditions(
    std::move(body.conditions), s.mesh.points, s.mesh.tets, totalMass, s.warnings);
  std::vector<char> fixed = body.pinned;
  if (!s.conditions.heldAxes().empty())
  {
    const std::vector<char> held = s.conditions.fullyHeld();
    fixed.resize(held.size(), 0);
    for (std::size_t i = 0; i < held.size(); ++i)
    {
      fixed[i] = fixed[i] || held[i];
    }
  }
  s.masses = distributeMass(s.topology, cellMasses.empty() ? s.constants.restVolume : cellMasses,
    totalMass, body.material.massDistribution, body.material.maxInverseMass, fixed);
  s.conditions.setMasses(s.masses.mass);
  if (s.masses.truncatedCount > 0)
  {
    std::ostringstream message;
    message << s.masses.truncatedCount << " inverse masses were truncated to "
            << body.material.maxInverseMass << " 1/kg; the total mass grew to "
            << s.masses.totalMass << " kg.";
    s.warnings.push_back(message.str());
  }

  s.scene.floor.normal.normalize();
  if (s.scene.floorActive())
  {
    std::size_t below = 0;
    for (const Vec3& p : s.mesh.points)
    {
      below += (p - s.scene.floor.origin).dot(s.scene.floor.normal) < 0.0 ? 1 : 0;
    }
    if (below > 0)
    {
      // The steppers lift each free body onto the floor at t = 0 (tet_body_contacts.h).
      s.warnings.push_back(std::to_string(below) +
        " points start below the floor: each body without pinned points is lifted onto it at "
        "t = 0 without velocity; pinned ones are pushed onto it in the first step. Move "
        "FloorOrigin below the body to drop it instead.");
    }
  }
  s.selfWeight = selfWeightStrain(s.mesh, s.constants.restVolume, body.material, s.scene.gravity);
  const bool held = s.scene.floorActive() || std::find(fixed.begin(), fixed.end(), 1) != fixed.end() ||
    !s.conditions.heldAxes().empty();
  if (const std::string collapse = selfWeightWarning(s.selfWeight); held && !collapse.empty())
  {
    s.warnings.push_back(collapse);
  }
  if (s.scene.collisions.bodiesCollide())
  {
    // Bodies placed inside each other are pushed apart at a bounded speed; say so and by how much.
    const std::string overlap =
      startOverlapWarning(findStartOverlaps(tetBodyGeometry(s.mesh, s.scene.collisions), s.mesh.points));
    if (!overlap.empty())
    {
      s.warnings.push_back(overlap);
    }
  }
  chooseStep(s);
  return s;
}

DynamicState restState(const MassSpringSetup& setup)
{
  DynamicState state;
  state.positions = setup.mesh.points;
  state.velocities.assign(setup.mesh.points.size(), Vec3::Zero());
  return state;
}

StepCost stepCostOf(const MassSpringSetup& s)
{
  return { s.step, s.stableStep, s.undampedStableStep, s.constants.maxDampingTime,
    s.scene.integrator, s.topology.tets.size() };
}

std::string longRunWarning(const StepCost& s, double duration)
{
  if (!(duration > 0.0) || !(s.step > 0.0))
  {
    return {};
  }
  const double steps = std::ceil(duration / s.step);
  const double evaluationsPerStep = factsOf(s.integrator).forceEvaluationsPerStep;
  const double seconds = steps * evaluationsPerStep *
    static_cast<double>(std::max<std::size_t>(1, s.tetCount)) / kTetStepsPerSecond;
  if (steps <= 1.0e6 && seconds <= 60.0)
  {
    return {};
  }
  std::ostringstream message;
  message.precision(3);
  message << "Simulating " << duration << " s takes " << steps << " steps of " << s.step
          << " s: about ";
  if (seconds < 120.0)
  {
    message << seconds << " s";
  }
  else if (seconds < 7200.0)
  {
    message << seconds / 60.0 << " minutes";
  }
  else
  {
    message << seconds / 3600.0 << " hours";
  }
  message << " on 2 cores. ";
  const bool dampingLimited = s.stableStep > 0.0 && s.undampedStableStep > 2.0 * s.stableStep;
  if (dampingLimited)
  {
    message << "The step is limited by damping (a damping time of " << s.maxDampingTime
            << " s overdamps the stiff modes): with DampingTime 0 the stable step would be "
            << s.undampedStableStep << " s (" << s.undampedStableStep / s.stableStep
            << "x fewer steps). ";
  }
  message << "Remedies: an implicit integrator (Integrator = Implicit Euler, stable at one step "
             "per frame: about 11x faster per simulated second on a 157k-tet TetGen mesh in "
             "bench_implicit, at the price of numerical damping), a shorter EndTime, a softer "
             "material (lower YoungsModulus)";
  if (dampingLimited)
  {
    message << ", less damping (DampingTime)";
  }
  message << ", or MaxInverseMass to cap the lightest points (Soft Body Mesh Quality suggests a "
             "value). The run reports progress and can be aborted.";
  return message.str();
}

bool hasDiverged(const SceneSettings& scene, double maxStretch, bool finiteVelocities)
{
  // Written so that a NaN stretch counts as diverged.
  return !(maxStretch <= scene.divergenceStretch && finiteVelocities);
}

std::string divergenceMessage(const DynamicState& state, double maxStretch,
  bool finiteVelocities, double step, double stableStep, const SelfWeight& selfWeight)
{
  std::ostringstream message;
  message << "The simulation blew up at t = " << state.time << " s (step " << state.stepCount
          << "): ";
  if (std::isnan(maxStretch) || !finiteVelocities)
  {
    message << "the state became non-finite";
  }
  else
  {
    message << "a spring stretched to " << maxStretch << " times its rest length";
  }
  if (selfWeight.strain >= kCollapsingSelfWeightStrain)
  {
    // Its weight alone crushes it: a smaller step would only take longer to blow up.
    message << ". " << selfWeightWarning(selfWeight);
    return message.str();
  }
  message << ". Time step " << step << " s, estimated stable step " << stableStep
          << " s; reduce TimeStep (0 = automatic), add damping or use a symplectic integrator.";
  return message.str();
}

} // namespace softbody
