#include "softbody/pbd/pbd_reordered.h"

#include "softbody/common/errors.h"
#include "softbody/pbd/pbd_simulation.h"

namespace softbody
{
namespace
{
bool indicesValid(const PbdBody& body)
{
  const std::size_t n = body.points.size();
  auto valid = [n](std::int32_t i) { return i >= 0 && std::size_t(i) < n; };
  for (const Tet& t : body.tets)
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

PbdBody reorderParticles(const PbdBody& body, const Reordering& reordering)
{
  PbdBody stored = body;
  const Order& slot = reordering.vertexSlot;
  stored.points = toStorageOrder(body.points, reordering.vertexOrder);
  for (Tet& t : stored.tets)
  {
    for (std::int32_t& v : t)
    {
      v = slot[static_cast<std::size_t>(v)];
    }
  }
  for (auto& l : stored.links)
  {
    l = { slot[static_cast<std::size_t>(l[0])], slot[static_cast<std::size_t>(l[1])] };
  }
  for (auto& triangle : stored.surfaceTriangles)
  {
    for (std::int32_t& v : triangle)
    {
      v = slot[static_cast<std::size_t>(v)];
    }
  }
  stored.pointMass = toStorageOrder(body.pointMass, reordering.vertexOrder);
  stored.pinned = toStorageOrder(body.pinned, reordering.vertexOrder);
  for (Condition& c : stored.conditions)
  {
    for (std::int32_t& p : c.points)
    {
      p = slot[static_cast<std::size_t>(p)];
    }
  }
  return stored;
}

std::unique_ptr<Simulation> makePbdSimulation(
  PbdBody body, const PbdSettings& settings, VertexOrdering ordering, PbdSimulation** solver)
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
      computeReordering(ordering, body.points, body.tets, body.links, false);
    auto simulation = std::make_unique<PbdSimulation>(reorderParticles(body, reordering), settings);
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
