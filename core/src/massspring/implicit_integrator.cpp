#include "softbody/massspring/implicit_integrator.h"

#include "softbody/massspring/implicit_euler.h"
#include "softbody/massspring/projective_dynamics.h"
#include "softbody/massspring/static_solve.h"

#include <stdexcept>
#include <string>

namespace softbody
{

std::unique_ptr<ImplicitIntegrator> makeImplicitIntegrator(const SceneSettings& scene,
  const Topology& topology, const BodyElements& elements, const PointMasses& masses,
  const std::vector<Vec3>& restPositions, const std::vector<Vec3>& positions)
{
  switch (scene.integrator)
  {
    case Integrator::ImplicitEuler:
      return std::make_unique<ImplicitEulerStepper>(topology, elements, masses, scene);
    case Integrator::ProjectiveDynamics:
      return std::make_unique<ProjectiveDynamicsStepper>(
        topology, elements, masses, restPositions, scene);
    case Integrator::Static:
      return std::make_unique<StaticStepper>(topology, elements, masses, scene, positions);
    default:
      throw std::logic_error(std::string("makeImplicitIntegrator: ") +
        integratorName(scene.integrator) + " is not implicit");
  }
}

} // namespace softbody
