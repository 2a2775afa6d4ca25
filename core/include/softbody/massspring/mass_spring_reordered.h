// Mass-spring steppers built on a body renumbered for memory locality (mesh/reorder.h), seen in
// the input's order. The CPU stepper, the GPU stepper and every integrator they dispatch to
// share this one boundary: the body is reordered before their set-up, their outputs mapped back
// after, and their own code does not change.
#pragma once

#include "softbody/massspring/mass_spring_settings.h"
#include "softbody/mesh/reorder.h"

#include <functional>
#include <memory>

namespace softbody
{

/// Builds a stepper from a body (the CPU or the GPU one); may return null (no GPU context).
using MassSpringFactory = std::function<std::unique_ptr<Simulation>(Body)>;

/// `make` on the body reordered by `ordering` (points, and tets by their points), wrapped in a
/// ReorderedSimulation so every output is in the input's order; `make(body)` itself for
/// VertexOrdering::Input. The mesh is validated in the input's order first, so a warning about
/// inverted tets names an input cell; a body that anything refuses is built again as given, so
/// the refusal (InvalidInputError) is exactly the one the unreordered stepper gives.
/// Returns null where `make` does.
std::unique_ptr<Simulation> buildReorderedMassSpring(Body body,
  const SceneSettings& scene, VertexOrdering ordering, const MassSpringFactory& make);

/// The CPU stepper (MassSpringSimulation) on the reordered body.
std::unique_ptr<Simulation> makeMassSpringSimulation(Body body,
  const SceneSettings& scene, VertexOrdering ordering = kDefaultVertexOrdering);

} // namespace softbody
