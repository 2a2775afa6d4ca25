#include "softbody/massspring/implicit_integrator.h"

#include "softbody/massspring/implicit_euler.h"
#include "softbody/massspring/projective_dynamics.h"

#include <stdexcept>
#include <string>

namespace softbody
{

std::unique_ptr<ImplicitIntegrator> makeImplicitIntegrator(const SceneSettings& scene,
  const Topology& topology, const ElementConstants& constants, const PointMasses& masses,
  const std::vector<Vec3>& restPositions)
{
  switch (scene.integrator)
  {
    case Integrator::ImplicitEuler:
      return std::make_unique<ImplicitEulerStepper>(topology, constants, masses, scene);
    case Integrator::ProjectiveDynamics:
      return std::make_unique<ProjectiveDynamicsStepper>(
        topology, constants, masses, restPositions, scene);
    default:
      throw std::logic_error(std::string("makeImplicitIntegrator: ") +
        integratorName(scene.integrator) + " is not implicit");
  }
}

} // namespace softbody
