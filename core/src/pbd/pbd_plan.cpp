#include "softbody/pbd/pbd_plan.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace softbody
{
namespace
{

/// Whether a constraint type of this material can move a particle. Per-element compliances
/// (XPBD from Young's modulus) are infinite where the element has no stiffness.
bool canMove(const PbdSettings& settings, const ConstraintMaterial& material,
  const std::vector<double>& perElementCompliance)
{
  if (settings.formulation == PbdFormulation::Pbd)
  {
    return material.stiffness > 0.0;
  }
  if (perElementCompliance.empty())
  {
    return std::isfinite(material.compliance);
  }
  return std::any_of(perElementCompliance.begin(), perElementCompliance.end(),
    [](double alpha) { return std::isfinite(alpha); });
}

} // namespace

const char* pbdSolverName(PbdSolver solver, double relaxation)
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

StepPlan planPbd(const PbdSettings& settings, const DistanceBatch& links,
  const TetElasticBatch& tetElasticity, const VolumeBatch& volumes,
  const AttachmentBatch& attachments, bool collisions)
{
  const std::string solver = std::string(settings.formulation == PbdFormulation::Xpbd ? "XPBD " : "PBD ") +
    pbdSolverName(settings.solver, settings.relaxation);
  StepPlan plan;
  plan.add(Stage::Predict,
    settings.prediction == PbdPrediction::Verlet ? "Verlet" : "symplectic Euler");
  if (collisions)
  {
    plan.add(Stage::CollisionDetect, "once per substep");
  }
  if (links.size() > 0 && canMove(settings, settings.links, links.compliance))
  {
    plan.add(Stage::SolveLinks, solver);
  }
  if (tetElasticity.size() > 0)
  {
    plan.add(Stage::SolveTetElasticity, solver + ", " + materialModelName(tetElasticity.model) +
      " (deviatoric + hydrostatic, together)");
  }
  if (volumes.size() > 0 && canMove(settings, settings.volumes, volumes.compliance))
  {
    plan.add(Stage::SolveVolumes, solver);
  }
  if (attachments.size() > 0 && canMove(settings, settings.attachments, {}))
  {
    plan.add(Stage::SolveAttachments, solver);
  }
  if (collisions)
  {
    // Friction acts in the solve (position level); only restitution needs the velocity pass.
    const CollisionSettings& c = settings.collisions;
    // With tet volumes, the tets with a corner held by an obstacle are kept from being crushed
    // by the contacts, after the last iteration (pbd_held_tets.cpp).
    const bool heldTets = plan.runs(Stage::SolveVolumes) || plan.runs(Stage::SolveTetElasticity);
    std::string detail = c.staticFriction > 0.0 || c.dynamicFriction > 0.0 ? "with friction" : "frictionless";
    plan.add(Stage::SolveContacts, heldTets ? detail + ", held tets kept from crushing" : detail);
  }
  if (settings.residualTolerance > 0.0)
  {
    plan.add(Stage::Residual, "every iteration (tolerance)");
  }
  else if (settings.reportConvergence)
  {
    plan.add(Stage::Residual, "last step of each frame");
  }
  plan.add(Stage::UpdateVelocities);
  if (collisions && settings.collisions.restitution > 0.0)
  {
    plan.add(Stage::ContactResponse, "restitution");
  }
  // A yield without creep never changes a rest length, so only breaking or flowing links
  // need the pass.
  if (settings.breakingStrain > 0.0 || (settings.plasticYield > 0.0 && settings.plasticCreep > 0.0))
  {
    plan.add(Stage::UpdateLinks);
  }
  plan.add(Stage::DivergenceCheck);
  return plan;
}

} // namespace softbody
