#include "softbody/massspring/mass_spring_reordered.h"

#include "softbody/common/errors.h"
#include "softbody/massspring/mass_spring_simulation.h"

#include <algorithm>

namespace softbody
{

BodyDescription reorderBody(const BodyDescription& body, const Reordering& reordering)
{
  BodyDescription stored;
  stored.mesh.points = toStorageOrder(body.mesh.points, reordering.vertexOrder);
  stored.mesh.tets = reorderTets(body.mesh.tets, reordering);
  stored.pinned = toStorageOrder(body.pinned, reordering.vertexOrder);
  stored.material = body.material;
  CellMaterial& cells = stored.material.cells;
  cells.youngsModulus = toStorageOrder(cells.youngsModulus, reordering.tetOrder);
  cells.poissonRatio = toStorageOrder(cells.poissonRatio, reordering.tetOrder);
  cells.density = toStorageOrder(cells.density, reordering.tetOrder);
  stored.conditions = body.conditions;
  const Order slot = inverseOrder(reordering.vertexOrder);
  for (Condition& c : stored.conditions)
  {
    for (std::int32_t& p : c.points)
    {
      p = slot[static_cast<std::size_t>(p)];
    }
  }
  return stored;
}

std::unique_ptr<Simulation> buildReorderedMassSpring(BodyDescription body,
  const SceneSettings& scene, VertexOrdering ordering, const MassSpringFactory& make)
{
  if (ordering == VertexOrdering::Input)
  {
    return make(std::move(body));
  }
  std::unique_ptr<Simulation> inner;
  Reordering reordering;
  std::vector<std::string> meshWarnings;
  try
  {
    if (!body.pinned.empty() && body.pinned.size() != body.mesh.points.size())
    {
      throw InvalidInputError("pins"); // refused below, by the stepper itself
    }
    // Validated (and inverted tets re-oriented) in input order, so messages name input cells;
    // the stepper's own validation then finds nothing more to say about the tets.
    BodyDescription prepared;
    prepared.mesh = prepareTetMesh(body.mesh, scene.invertedTets, meshWarnings);
    prepared.pinned = body.pinned;
    prepared.material = body.material;
    prepared.conditions = body.conditions;
    std::vector<std::string> ignored; // said by the stepper itself
    validateConditions(body.conditions, body.mesh.points.size(), ignored);
    reordering = computeReordering(ordering, prepared.mesh.points, prepared.mesh.tets, {}, true);
    inner = make(reorderBody(prepared, reordering));
  }
  catch (const InvalidInputError&)
  {
    return make(std::move(body));
  }
  if (!inner)
  {
    return nullptr;
  }
  // The warnings of the input-order validation that the stepper, given tets already
  // re-oriented, does not repeat come first, where its own validation would put them.
  std::vector<std::string> warnings;
  const std::vector<std::string>& own = inner->warnings();
  for (const std::string& w : meshWarnings)
  {
    if (std::find(own.begin(), own.end(), w) == own.end())
    {
      warnings.push_back(w);
    }
  }
  if (!warnings.empty())
  {
    warnings.insert(warnings.end(), own.begin(), own.end());
  }
  return std::make_unique<ReorderedSimulation>(std::move(inner), std::move(reordering), std::move(warnings));
}

std::unique_ptr<Simulation> makeMassSpringSimulation(BodyDescription body,
  const SceneSettings& scene, VertexOrdering ordering)
{
  return buildReorderedMassSpring(std::move(body), scene, ordering, [&](BodyDescription stored) {
    return std::unique_ptr<Simulation>(std::make_unique<MassSpringSimulation>(std::move(stored), scene));
  });
}

} // namespace softbody
