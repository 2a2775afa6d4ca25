#include "softbody/mesh/reorder.h"

#include "softbody/common/errors.h"
#include "softbody/common/morton.h"

#include <algorithm>
#include <numeric>
#include <utility>

namespace softbody
{
namespace
{

/// Symmetric vertex adjacency (tet edges and links) as CSR, neighbours sorted, no repeats.
void buildAdjacency(std::size_t n, const std::vector<Tet>& tets,
  const std::vector<std::array<std::int32_t, 2>>& links, std::vector<std::int32_t>& offsets,
  std::vector<std::int32_t>& neighbours)
{
  std::vector<std::pair<std::int32_t, std::int32_t>> pairs;
  pairs.reserve(tets.size() * 12 + links.size() * 2);
  auto add = [&](std::int32_t a, std::int32_t b) {
    if (a == b || a < 0 || b < 0 || std::size_t(a) >= n || std::size_t(b) >= n)
    {
      return;
    }
    pairs.emplace_back(a, b);
    pairs.emplace_back(b, a);
  };
  for (const Tet& t : tets)
  {
    for (int i = 0; i < 4; ++i)
    {
      for (int j = i + 1; j < 4; ++j)
      {
        add(t[i], t[j]);
      }
    }
  }
  for (const auto& l : links)
  {
    add(l[0], l[1]);
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  offsets.assign(n + 1, 0);
  for (const auto& p : pairs)
  {
    ++offsets[static_cast<std::size_t>(p.first) + 1];
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    offsets[i + 1] += offsets[i];
  }
  neighbours.resize(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k)
  {
    neighbours[k] = pairs[k].second; // pairs are sorted by first, then second
  }
}

} // namespace

const char* vertexOrderingName(VertexOrdering ordering)
{
  switch (ordering)
  {
    case VertexOrdering::Input:
      return "input";
    case VertexOrdering::Morton:
      return "Morton";
    case VertexOrdering::ReverseCuthillMcKee:
      return "RCM";
  }
  return "?";
}

Order inverseOrder(const Order& order)
{
  Order slot(order.size());
  for (std::size_t k = 0; k < order.size(); ++k)
  {
    slot[static_cast<std::size_t>(order[k])] = static_cast<std::int32_t>(k);
  }
  return slot;
}

bool isPermutation(const Order& order, std::size_t n)
{
  if (order.size() != n)
  {
    return false;
  }
  std::vector<char> seen(n, 0);
  for (std::int32_t i : order)
  {
    if (i < 0 || std::size_t(i) >= n || seen[static_cast<std::size_t>(i)])
    {
      return false;
    }
    seen[static_cast<std::size_t>(i)] = 1;
  }
  return true;
}

Order mortonOrder(const std::vector<Vec3>& points)
{
  const std::size_t n = points.size();
  Vec3 low = Vec3::Constant(0.0), high = Vec3::Constant(0.0);
  bool any = false;
  for (const Vec3& p : points)
  {
    if (!p.allFinite())
    {
      continue;
    }
    low = any ? Vec3(low.cwiseMin(p)) : p;
    high = any ? Vec3(high.cwiseMax(p)) : p;
    any = true;
  }
  // One scale for all axes keeps the curve's cells cubes (a flat body stays well ordered).
  const double extent = (high - low).maxCoeff();
  const double scale = extent > 0.0 ? double((1u << 21) - 1) / extent : 0.0;
  std::vector<std::pair<std::uint64_t, std::int32_t>> keyed(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    std::uint64_t code = 0;
    if (points[i].allFinite())
    {
      for (int axis = 0; axis < 3; ++axis)
      {
        const double q = std::clamp((points[i][axis] - low[axis]) * scale, 0.0, double((1u << 21) - 1));
        code |= spreadBits(static_cast<std::uint64_t>(q)) << axis;
      }
    }
    keyed[i] = { code, static_cast<std::int32_t>(i) };
  }
  std::sort(keyed.begin(), keyed.end());
  Order order(n);
  for (std::size_t k = 0; k < n; ++k)
  {
    order[k] = keyed[k].second;
  }
  return order;
}

Order reverseCuthillMcKeeOrder(std::size_t n, const std::vector<Tet>& tets,
  const std::vector<std::array<std::int32_t, 2>>& links)
{
  std::vector<std::int32_t> offsets, adjacent;
  buildAdjacency(n, tets, links, offsets, adjacent);
  auto degree = [&](std::int32_t v) { return offsets[std::size_t(v) + 1] - offsets[std::size_t(v)]; };

  std::vector<char> placed(n, 0);
  std::vector<std::int32_t> level(n, -1);
  Order order;
  order.reserve(n);

  // Breadth-first levels from `root` over the unplaced vertices; returns the last level's
  // vertex of least degree and the eccentricity of root.
  std::vector<std::int32_t> queue;
  std::vector<std::int32_t> touched;
  auto farthest = [&](std::int32_t root, int& eccentricity) {
    queue.assign(1, root);
    touched.assign(1, root);
    level[std::size_t(root)] = 0;
    for (std::size_t head = 0; head < queue.size(); ++head)
    {
      const std::int32_t v = queue[head];
      for (std::int32_t k = offsets[std::size_t(v)]; k < offsets[std::size_t(v) + 1]; ++k)
      {
        const std::int32_t u = adjacent[std::size_t(k)];
        if (!placed[std::size_t(u)] && level[std::size_t(u)] < 0)
        {
          level[std::size_t(u)] = level[std::size_t(v)] + 1;
          queue.push_back(u);
          touched.push_back(u);
        }
      }
    }
    eccentricity = level[std::size_t(queue.back())];
    std::int32_t best = queue.back();
    for (auto it = queue.rbegin(); it != queue.rend() && level[std::size_t(*it)] == eccentricity; ++it)
    {
      if (degree(*it) < degree(best) || (degree(*it) == degree(best) && *it < best))
      {
        best = *it;
      }
    }
    for (std::int32_t v : touched)
    {
      level[std::size_t(v)] = -1;
    }
    return best;
  };

  std::vector<std::int32_t> candidates;
  for (std::size_t start = 0; start < n; ++start)
  {
    if (placed[start] || degree(std::int32_t(start)) == 0)
    {
      continue;
    }
    // George-Liu: walk to the far end of the level structure while its depth grows.
    std::int32_t root = static_cast<std::int32_t>(start);
    int eccentricity = 0;
    std::int32_t next = farthest(root, eccentricity);
    for (int round = 0; round < 8; ++round)
    {
      int nextEccentricity = 0;
      const std::int32_t beyond = farthest(next, nextEccentricity);
      if (nextEccentricity <= eccentricity)
      {
        break;
      }
      root = next;
      eccentricity = nextEccentricity;
      next = beyond;
    }
    root = next;
    // Cuthill-McKee from root: neighbours by increasing degree (ties by index).
    const std::size_t first = order.size();
    order.push_back(root);
    placed[std::size_t(root)] = 1;
    for (std::size_t head = first; head < order.size(); ++head)
    {
      const std::int32_t v = order[head];
      candidates.clear();
      for (std::int32_t k = offsets[std::size_t(v)]; k < offsets[std::size_t(v) + 1]; ++k)
      {
        const std::int32_t u = adjacent[std::size_t(k)];
        if (!placed[std::size_t(u)])
        {
          placed[std::size_t(u)] = 1;
          candidates.push_back(u);
        }
      }
      std::sort(candidates.begin(), candidates.end(), [&](std::int32_t a, std::int32_t b) {
        return degree(a) < degree(b) || (degree(a) == degree(b) && a < b);
      });
      order.insert(order.end(), candidates.begin(), candidates.end());
    }
  }
  std::reverse(order.begin(), order.end());
  for (std::size_t i = 0; i < n; ++i)
  {
    if (!placed[i])
    {
      order.push_back(static_cast<std::int32_t>(i));
    }
  }
  return order;
}

Order tetOrderByVertices(const std::vector<Tet>& tets, const Order& vertexSlot)
{
  std::vector<std::pair<Tet, std::int32_t>> keyed(tets.size());
  for (std::size_t t = 0; t < tets.size(); ++t)
  {
    Tet key;
    for (int c = 0; c < 4; ++c)
    {
      const std::int32_t v = tets[t][c];
      key[c] = vertexSlot.empty() ? v : vertexSlot[static_cast<std::size_t>(v)];
    }
    std::sort(key.begin(), key.end());
    keyed[t] = { key, static_cast<std::int32_t>(t) };
  }
  std::sort(keyed.begin(), keyed.end());
  Order order(tets.size());
  for (std::size_t t = 0; t < tets.size(); ++t)
  {
    order[t] = keyed[t].second;
  }
  return order;
}

Reordering computeReordering(VertexOrdering ordering, const std::vector<Vec3>& points,
  const std::vector<Tet>& tets, const std::vector<std::array<std::int32_t, 2>>& links,
  bool orderTets)
{
  Reordering r;
  switch (ordering)
  {
    case VertexOrdering::Input:
      r.vertexOrder.resize(points.size());
      std::iota(r.vertexOrder.begin(), r.vertexOrder.end(), 0);
      break;
    case VertexOrdering::Morton:
      r.vertexOrder = mortonOrder(points);
      break;
    case VertexOrdering::ReverseCuthillMcKee:
      r.vertexOrder = reverseCuthillMcKeeOrder(points.size(), tets, links);
      break;
  }
  r.vertexSlot = inverseOrder(r.vertexOrder);
  if (orderTets)
  {
    r.tetOrder = tetOrderByVertices(tets, r.vertexSlot);
  }
  return r;
}

std::vector<Tet> reorderTets(const std::vector<Tet>& tets, const Reordering& reordering)
{
  std::vector<Tet> out = toStorageOrder(tets, reordering.tetOrder);
  for (Tet& t : out)
  {
    for (std::int32_t& v : t)
    {
      v = reordering.vertexSlot[static_cast<std::size_t>(v)];
    }
  }
  return out;
}

ReorderedSimulation::ReorderedSimulation(std::unique_ptr<Simulation> inner, Reordering reordering,
  std::vector<std::string> warnings)
  : Inner(std::move(inner))
  , Map(std::move(reordering))
  , Warnings(std::move(warnings))
{
  Rest = toInputOrder(Inner->restPositions(), Map.vertexOrder);
  InverseMass = toInputOrder(Inner->inverseMasses(), Map.vertexOrder);
}

AdvanceStatus ReorderedSimulation::advance(double endTime, const ProgressCallback& progress)
{
  Stale = true; // also when advance() throws: the stepper's state has moved
  return Inner->advance(endTime, progress);
}

const DynamicState& ReorderedSimulation::state() const
{
  const DynamicState& in = Inner->state();
  if (Stale || Out.stepCount != in.stepCount || Out.time != in.time)
  {
    Out.positions = toInputOrder(in.positions, Map.vertexOrder);
    Out.velocities = toInputOrder(in.velocities, Map.vertexOrder);
    Out.time = in.time;
    Out.stepCount = in.stepCount;
    Out.previousStep = in.previousStep;
    Out.previousPositions = toInputOrder(in.previousPositions, Map.vertexOrder);
    Out.previousVelocities = toInputOrder(in.previousVelocities, Map.vertexOrder);
    Out.proposedStep = in.proposedStep;
    Out.linkRestLengths = in.linkRestLengths;
    Out.linkBroken = in.linkBroken;
    Out.impactSpeeds = toInputOrder(in.impactSpeeds, Map.vertexOrder);
    Out.impactNormals = toInputOrder(in.impactNormals, Map.vertexOrder);
    Out.supportForces = toInputOrder(in.supportForces, Map.vertexOrder);
    Out.previousAccelerations = toInputOrder(in.previousAccelerations, Map.vertexOrder);
    Stale = false;
  }
  return Out;
}

void ReorderedSimulation::restoreState(const DynamicState& snapshot)
{
  if (snapshot.positions.size() != Map.vertexOrder.size() ||
    snapshot.velocities.size() != Map.vertexOrder.size())
  {
    throw InvalidInputError("The snapshot does not belong to this simulation.");
  }
  DynamicState stored = snapshot;
  stored.positions = toStorageOrder(snapshot.positions, Map.vertexOrder);
  stored.velocities = toStorageOrder(snapshot.velocities, Map.vertexOrder);
  stored.previousPositions = toStorageOrder(snapshot.previousPositions, Map.vertexOrder);
  stored.previousVelocities = toStorageOrder(snapshot.previousVelocities, Map.vertexOrder);
  stored.impactSpeeds = toStorageOrder(snapshot.impactSpeeds, Map.vertexOrder);
  stored.impactNormals = toStorageOrder(snapshot.impactNormals, Map.vertexOrder);
  stored.supportForces = toStorageOrder(snapshot.supportForces, Map.vertexOrder);
  stored.previousAccelerations = toStorageOrder(snapshot.previousAccelerations, Map.vertexOrder);
  Inner->restoreState(stored);
  Out = snapshot;
  Stale = false;
}

std::vector<double> ReorderedSimulation::tetVolumeRatios() const
{
  return toInputOrder(Inner->tetVolumeRatios(), Map.tetOrder);
}

TetStressField ReorderedSimulation::stressField() const
{
  TetStressField field = Inner->stressField();
  field.greenStrain = toInputOrder(field.greenStrain, Map.tetOrder);
  field.cauchyStress = toInputOrder(field.cauchyStress, Map.tetOrder);
  field.vonMises = toInputOrder(field.vonMises, Map.tetOrder);
  field.energyDensity = toInputOrder(field.energyDensity, Map.tetOrder);
  return field;
}

bool ReorderedSimulation::setConditionValues(const std::vector<Condition>& conditions)
{
  std::vector<Condition> stored = conditions;
  for (Condition& c : stored)
  {
    for (std::int32_t& p : c.points)
    {
      if (p < 0 || static_cast<std::size_t>(p) >= Map.vertexSlot.size())
      {
        return false;
      }
      p = Map.vertexSlot[static_cast<std::size_t>(p)];
    }
  }
  return Inner->setConditionValues(stored);
}

ConditionReadout ReorderedSimulation::conditionReadout() const
{
  ConditionReadout readout = Inner->conditionReadout();
  readout.reactions = toInputOrder(readout.reactions, Map.vertexOrder);
  return readout;
}

} // namespace softbody
