#include "softbody/massspring/mass_spring_plan.h"

#include <string>

namespace softbody
{
namespace
{

void addIntegration(StepPlan& plan, const SceneSettings& scene, const std::string& elements)
{
  const IntegratorFacts& integrator = factsOf(scene.integrator);
  plan.add(Stage::Forces,
    integrator.forcesDetail ? elements + ", " + integrator.forcesDetail : elements);
  plan.add(Stage::Integrate, integrator.name);
  if (integrator.linearSolve)
  {
    plan.add(Stage::LinearSolve, integrator.linearSolve);
  }
  if (scene.strainLimit > 0.0)
  {
    plan.add(Stage::StrainLimit);
  }
}

/// The implicit integrators' floor: held in the solve, with Coulomb friction after it
/// (implicit_solve.cpp) unless both coefficients are 0.
const char* implicitFloorLabel(const CollisionSettings& contact)
{
  return contact.staticFriction > 0.0 || contact.dynamicFriction > 0.0 ? "active set in the solve, with friction"
                                                                        : "active set in the solve, frictionless";
}

} // namespace

std::string elementPassLabel(MaterialModel model, bool hasVolumeTerm)
{
  // The network's pass walks the springs and, only when some tet has a volume stiffness or
  // damping, the tets (ElementConstants::hasVolumeTerm).
  if (isContinuum(model))
  {
    return std::string("tets, ") + materialModelName(model);
  }
  return hasVolumeTerm ? "springs + volumes" : "springs";
}

StepPlan planMassSpring(const MassSpringSetup& setup)
{
  const SceneSettings& scene = setup.scene;
  StepPlan plan;
  addIntegration(plan, scene, elementPassLabel(setup.model, setup.constants.hasVolumeTerm));
  if (scene.floorActive())
  {
    plan.add(Stage::Floor, isImplicit(scene.integrator) ? implicitFloorLabel(scene.collisions) : "");
  }
  plan.add(Stage::DivergenceCheck);
  return plan;
}

StepPlan planMassSpring(const SceneSettings& scene, const std::string& elements, bool hasObstacles)
{
  StepPlan plan;
  addIntegration(plan, scene, elements);
  const bool implicit = isImplicit(scene.integrator);
  // The implicit integrators keep the floor and the obstacles in their solve (a step may not
  // cross them); the bodies' contacts are resolved after the step like the explicit
  // integrators' contacts.
  if (implicit && scene.floorActive())
  {
    plan.add(Stage::Floor, implicitFloorLabel(scene.collisions));
  }
  const bool bodies = scene.collisions.bodiesCollide();
  const bool detectedFloor = !implicit && scene.floorActive();
  if (scene.collisions.on() && (detectedFloor || hasObstacles || bodies))
  {
    std::string what = detectedFloor ? "floor" : "";
    auto join = [&](const std::string& part) { what += (what.empty() ? "" : ", ") + part; };
    if (hasObstacles)
    {
      join(implicit ? "obstacles (held in the solve)" : "obstacles");
    }
    if (bodies)
    {
      const std::string label = scene.collisions.selfCollides() ? "bodies, self" : "bodies";
      join(implicit ? label + " (faces held in the solve)" : label);
    }
    plan.add(Stage::CollisionDetect, what);
    plan.add(Stage::Contacts, "projection + velocity response");
  }
  plan.add(Stage::DivergenceCheck);
  return plan;
}

} // namespace softbody
