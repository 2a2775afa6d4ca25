#include "softbody/pbd/pbd_reordered.h"

#include "softbody/common/errors.h"
#include "softbody/pbd/pbd_simulation.h"

namespace softbody
{
namespace
{
bool indicesValid(const Body& body)
{
  const std::size_t n = body.mesh.points.size();
  auto valid = [n](std::int32_t i) { return i >= 0 && std::size_t(i) < n; };
  for (const Tet& t : body.mesh.tets)
  {
    for (std::int32_t i : t)
    {
      if (!valid(i))
      {
        return false;
      }
    }
  }
  for (const auto& l : body.links)
  {
    if (!valid(l[0]) || !valid(l[1]))
    {
      return false;
    }
  }
  for (const auto& triangle : body.surfaceTriangles)
  {
    for (std::int32_t i : triangle)
    {
      if (!valid(i))
      {
        return false;
      }
    }
  }
  return (body.pointMass.empty() || body.pointMass.size() == n) &&
    (body.pinned.empty() || body.pinned.size() == n);
}
} // namespace

std::unique_ptr<Simulation> makePbdSimulation(
  Body body, const PbdSettings& settings, VertexOrdering ordering, PbdSimulation** solver)
{
  auto plain = [&]() {
    auto simulation = std::make_unique<PbdSimulation>(std::move(body), settings);
    if (solver)
    {
      *solver = simulation.get();
    }
    return std::unique_ptr<Simulation>(std::move(simulation));
  };
  if (ordering == VertexOrdering::Input || !indicesValid(body))
  {
    return plain(); // an invalid body is refused with the input's own indices
  }
  try
  {
    Reordering reordering =
      computeReordering(ordering, body.mesh.points, body.mesh.tets, body.links, false);
    auto simulation = std::make_unique<PbdSimulation>(reorderBody(body, reordering), settings);
    PbdSimulation* inner = simulation.get();
    auto wrapped = std::make_unique<ReorderedSimulation>(std::move(simulation), std::move(reordering));
    if (solver)
    {
      *solver = inner;
    }
    return wrapped;
  }
  catch (const InvalidInputError&)
  {
    return plain();
  }
}

} // namespace softbody
