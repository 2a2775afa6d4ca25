#include "softbody/massspring/mass_spring_plan.h"

#include <string>

namespace softbody
{

StepPlan planMassSpring(const MassSpringSetup& setup)
{
  const SceneSettings& scene = setup.scene;
  StepPlan plan;
  // The force pass walks the springs and, only when some tet has a volume stiffness or
  // damping, the tets (ElementConstants::hasVolumeTerm).
  const std::string elements = setup.constants.hasVolumeTerm ? "springs + volumes" : "springs";
  switch (scene.integrator)
  {
    case Integrator::ImplicitEuler:
      // Newton: gradient, PSD Hessian and line-search energies; then CG on the Hessian.
      plan.add(Stage::Forces, elements + ", gradient + Hessian");
      plan.add(Stage::Integrate, integratorName(scene.integrator));
      plan.add(Stage::LinearSolve, "block-Jacobi PCG");
      break;
    case Integrator::ProjectiveDynamics:
      // Local step: the element pass (projections = gradient); global: prefactored solves.
      plan.add(Stage::Forces, elements + ", local step");
      plan.add(Stage::Integrate, integratorName(scene.integrator));
      plan.add(Stage::LinearSolve, "prefactored Cholesky");
      break;
    default:
      plan.add(Stage::Forces, elements);
      plan.add(Stage::Integrate, integratorName(scene.integrator));
      break;
  }
  if (scene.strainLimit > 0.0)
  {
    plan.add(Stage::StrainLimit);
  }
  if (scene.floorEnabled)
  {
    plan.add(Stage::Floor, isImplicit(scene.integrator) ? "active set in the solve" : "");
  }
  plan.add(Stage::DivergenceCheck);
  return plan;
}

} // namespace softbody
