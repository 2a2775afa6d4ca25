// PBD/XPBD steppers built on a body whose particles are renumbered for memory locality
// (mesh/reorder.h), seen in the input's order.
#pragma once

#include "softbody/mesh/reorder.h"
#include "softbody/scene/body.h"
#include "softbody/pbd/pbd_settings.h"

#include <memory>

namespace softbody
{

class PbdSimulation;

/// A PbdSimulation on the body's particles renumbered by `ordering`, wrapped in a
/// ReorderedSimulation so every output is in the input's order (the plain stepper for
/// VertexOrdering::Input). Tets and links keep their input indices, so `solver` (set to the
/// PbdSimulation inside when given) answers tetBroken / linkBroken / convergence in input
/// terms; it stores its tets sorted by their (renumbered) vertices itself. A body the stepper
/// refuses is built again as given, so the refusal is the one the unreordered stepper gives.
std::unique_ptr<Simulation> makePbdSimulation(Body body, const PbdSettings& settings,
  VertexOrdering ordering = kDefaultVertexOrdering, PbdSimulation** solver = nullptr);

} // namespace softbody
