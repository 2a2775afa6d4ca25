// The mass-spring planner: which stages one step runs, decided once from the prepared body
// and its settings. The CPU and GPU steppers both execute this plan.
#pragma once

#include "softbody/common/step_plan.h"
#include "softbody/massspring/mass_spring_setup.h"

#include <string>

namespace softbody
{

/// What the plan calls the element pass of a body: "springs", "springs + volumes" or
/// "tets, <model>".
std::string elementPassLabel(MaterialModel model, bool hasVolumeTerm);

/// The GPU stepper's plan: forces, integrate, then strain limit only when a limit is set,
/// floor only when there is a floor (its own floor pass), and the divergence check.
StepPlan planMassSpring(const MassSpringSetup& setup);

/// The CPU stepper's plan, where contacts go through the collision detector: forces,
/// integrate, strain limit when set; for the implicit integrators the floor as the active set
/// inside their solve; then collision detection and contacts (projection and velocity
/// response, contact_response.h) when anything can be touched: the floor (explicit
/// integrators), obstacles (`hasObstacles`), or other bodies and the body itself (Collisions
/// mode); the divergence check last.
StepPlan planMassSpring(const SceneSettings& scene, const std::string& elements, bool hasObstacles);

} // namespace softbody
