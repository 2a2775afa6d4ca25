#include "softbody/massspring/implicit_integrator.h"

#include "softbody/massspring/bdf2.h"
#include "softbody/massspring/implicit_euler.h"
#include "softbody/massspring/projective_dynamics.h"
#include "softbody/massspring/static_solve.h"
#include "softbody/massspring/vertex_block_descent.h"

#include <stdexcept>
#include <string>

namespace softbody
{

std::unique_ptr<ImplicitIntegrator> makeImplicitIntegrator(const SceneSettings& scene,
  const Topology& topology, const BodyElements& elements, const PointMasses& masses,
  const std::vector<Vec3>& restPositions, const std::vector<Vec3>& positions,
  const BoundaryConditions* conditions)
{
  std::unique_ptr<ImplicitIntegrator> integrator;
  switch (scene.integrator)
  {
    case Integrator::ImplicitEuler:
      integrator = std::make_unique<ImplicitEulerStepper>(topology, elements, masses, restPositions, scene);
      break;
    case Integrator::Bdf2:
      integrator = std::make_unique<Bdf2Stepper>(topology, elements, masses, restPositions, scene);
      break;
    case Integrator::ProjectiveDynamics:
      integrator = std::make_unique<ProjectiveDynamicsStepper>(
        topology, elements, masses, restPositions, scene);
      break;
    case Integrator::VertexBlockDescent:
      integrator = std::make_unique<VertexBlockDescentStepper>(topology, elements, masses, scene);
      break;
    case Integrator::Static:
      integrator = std::make_unique<StaticStepper>(topology, elements, masses, restPositions, scene, positions,
        conditions);
      break;
    default:
      throw std::logic_error(std::string("makeImplicitIntegrator: ") +
        integratorName(scene.integrator) + " is not implicit");
  }
  if (conditions && !conditions->empty())
  {
    integrator->potential().setConditions(conditions);
  }
  return integrator;
}

} // namespace softbody
