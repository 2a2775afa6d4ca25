#include "softbody/massspring/mass_spring_plan.h"

namespace softbody
{

StepPlan planMassSpring(const MassSpringSetup& setup)
{
  const SceneSettings& scene = setup.scene;
  StepPlan plan;
  // The force pass walks the springs and, only when some tet has a volume stiffness or
  // damping, the tets (ElementConstants::hasVolumeTerm).
  plan.add(Stage::Forces, setup.constants.hasVolumeTerm ? "springs + volumes" : "springs");
  plan.add(Stage::Integrate, integratorName(scene.integrator));
  if (scene.strainLimit > 0.0)
  {
    plan.add(Stage::StrainLimit);
  }
  if (scene.floorEnabled)
  {
    plan.add(Stage::Floor);
  }
  plan.add(Stage::DivergenceCheck);
  return plan;
}

} // namespace softbody
