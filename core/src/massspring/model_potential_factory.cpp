#include "softbody/massspring/model_potential_factory.h"

#include "softbody/material/spring_network.h"

namespace softbody
{

std::unique_ptr<IncrementalPotential> makeIncrementalPotential(const Topology& topology,
  const ElementConstants& constants, const PointMasses& masses, const Vec3& gravity)
{
  return std::make_unique<SpringNetworkPotential>(
    topology, SpringNetwork(topology, constants), masses, gravity);
}

} // namespace softbody
