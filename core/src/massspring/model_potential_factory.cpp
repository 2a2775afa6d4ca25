#include "softbody/massspring/model_potential_factory.h"

#include "softbody/material/spring_network.h"

#include <stdexcept>

namespace softbody
{

std::unique_ptr<IncrementalPotential> makeIncrementalPotential(const Topology& topology,
  const BodyElements& elements, const PointMasses& masses, const Vec3& gravity)
{
  if (!isContinuum(elements.model))
  {
    return std::make_unique<SpringNetworkPotential>(
      topology, SpringNetwork(topology, *elements.network), masses, gravity);
  }
  if (!elements.tets)
  {
    throw std::logic_error("makeIncrementalPotential: a continuum model without its constants");
  }
  return withElasticLaw(elements.model, [&](auto law) -> std::unique_ptr<IncrementalPotential> {
    using Model = TetElasticModel<decltype(law)>;
    return std::make_unique<ModelPotential<Model>>(
      topology, Model(topology, *elements.tets), masses, gravity);
  });
}

} // namespace softbody
