#include "softbody/massspring/mass_spring_reordered.h"

#include "softbody/common/errors.h"
#include "softbody/massspring/mass_spring_simulation.h"

#include <algorithm>

namespace softbody
{

std::unique_ptr<Simulation> buildReorderedMassSpring(Body body,
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
    Body prepared = body;
    prepared.mesh = prepareTetMesh(std::move(prepared.mesh), scene.invertedTets, meshWarnings);
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

std::unique_ptr<Simulation> makeMassSpringSimulation(Body body,
  const SceneSettings& scene, VertexOrdering ordering)
{
  return buildReorderedMassSpring(std::move(body), scene, ordering, [&](Body stored) {
    return std::unique_ptr<Simulation>(std::make_unique<MassSpringSimulation>(std::move(stored), scene));
  });
}

} // namespace softbody
