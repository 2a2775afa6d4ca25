// The mass-spring planner: which stages one step runs, decided once from the prepared body
// and its settings. The CPU and GPU steppers both execute this plan.
#pragma once

#include "softbody/common/step_plan.h"
#include "softbody/massspring/mass_spring_setup.h"

namespace softbody
{

/// forces, integrate, then strain limit only when a limit is set, floor only when there is a
/// floor, and the divergence check.
StepPlan planMassSpring(const MassSpringSetup& setup);

} // namespace softbody
