#include "softbody/scene/body.h"

namespace softbody
{

std::string Body::particleOnlyParts() const
{
  std::string parts;
  const auto add = [&parts](const std::string& part) {
    parts += (parts.empty() ? "" : ", ") + part;
  };
  if (!links.empty())
  {
    add(std::to_string(links.size()) + " links");
  }
  if (!linkStiffnessScale.empty())
  {
    add("link stiffness factors");
  }
  if (!pointMass.empty())
  {
    add("point masses");
  }
  if (!surfaceTriangles.empty())
  {
    add(std::to_string(surfaceTriangles.size()) + " surface triangles");
  }
  return parts;
}

Body reorderBody(const Body& body, const Reordering& reordering)
{
  Body stored = body;
  const Order& slot = reordering.vertexSlot;
  const auto renumber = [&slot](std::int32_t& v) { v = slot[static_cast<std::size_t>(v)]; };
  stored.mesh.points = toStorageOrder(body.mesh.points, reordering.vertexOrder);
  stored.mesh.tets = reorderTets(body.mesh.tets, reordering);
  CellMaterial& cells = stored.material.cells;
  cells.youngsModulus = toStorageOrder(cells.youngsModulus, reordering.tetOrder);
  cells.poissonRatio = toStorageOrder(cells.poissonRatio, reordering.tetOrder);
  cells.density = toStorageOrder(cells.density, reordering.tetOrder);
  for (auto& link : stored.links)
  {
    renumber(link[0]);
    renumber(link[1]);
  }
  for (auto& triangle : stored.surfaceTriangles)
  {
    for (std::int32_t& v : triangle)
    {
      renumber(v);
    }
  }
  stored.pointMass = toStorageOrder(body.pointMass, reordering.vertexOrder);
  stored.pinned = toStorageOrder(body.pinned, reordering.vertexOrder);
  for (Condition& condition : stored.conditions)
  {
    for (std::int32_t& p : condition.points)
    {
      renumber(p);
    }
  }
  return stored;
}

} // namespace softbody
