// Memory locality at set-up: a renumbering of the vertices (along a space-filling curve, or by
// reverse Cuthill-McKee) and an order of the tets by their renumbered vertices, so that the
// elements a loop visits one after the other touch vertices that lie close in memory.
//
// Meshes arrive in any order: TetGen numbers the surface points first and its Steiner points in
// the order it inserts them, so neighbours in space lie far apart in memory and every element
// pass misses the cache on most of its vertex reads. On a 179k-tet TetGen ellipsoid the force
// pass of a mass-spring step takes 2.3x longer than after a Morton sort.
//
// A stepper is built on the reordered body and wrapped in a ReorderedSimulation, which maps
// every output (state, rest positions, inverse masses, per-tet values) back to the input's
// order and every snapshot it is given into storage order: users, the frame cache and the
// skinning see the input's numbering. The steppers themselves do not know about it.
#pragma once

#include "softbody/common/geometry.h"
#include "softbody/common/simulation.h"

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace softbody
{

enum class VertexOrdering
{
  Input,                   ///< as given (no renumbering)
  Morton,                  ///< along a Z-order (Morton) curve through the rest positions
  ReverseCuthillMcKee      ///< breadth-first from a peripheral vertex, reversed (bandwidth)
};

const char* vertexOrderingName(VertexOrdering ordering);

/// The ordering the steppers' factories use by default, chosen by measurement
/// (tests/bench/bench_mass_spring and bench_pbd print all of them; see core/README.md).
constexpr VertexOrdering kDefaultVertexOrdering = VertexOrdering::Morton;

/// Storage index -> input index. Storage slot k holds input item order[k].
using Order = std::vector<std::int32_t>;

/// The inverse of an order: slot[input] = storage index.
Order inverseOrder(const Order& order);

/// True when `order` holds each of 0 .. n-1 exactly once.
bool isPermutation(const Order& order, std::size_t n);

/// Vertices sorted by the Morton code of their position quantized to 21 bits per axis over the
/// bounding box (ties keep the input order).
Order mortonOrder(const std::vector<Vec3>& points);

/// Reverse Cuthill-McKee on the graph of tet edges and links: each connected component from a
/// pseudo-peripheral vertex (George-Liu), neighbours by increasing degree, the whole reversed.
/// Vertices in no element come last, in input order.
Order reverseCuthillMcKeeOrder(std::size_t vertexCount, const std::vector<Tet>& tets,
  const std::vector<std::array<std::int32_t, 2>>& links = {});

/// Tets sorted by their corners renumbered with `vertexSlot` (inverse of the vertex order),
/// compared as sorted tuples: tets sharing low vertices come together.
Order tetOrderByVertices(const std::vector<Tet>& tets, const Order& vertexSlot);

/// How a body is stored: its vertex order and its tet order (empty tetOrder: input order).
struct Reordering
{
  Order vertexOrder; ///< storage vertex k is input vertex vertexOrder[k]
  Order vertexSlot;  ///< input vertex i is storage vertex vertexSlot[i]
  Order tetOrder;    ///< storage tet t is input tet tetOrder[t]; empty: not reordered
};

/// The reordering of a body for `ordering` (vertexOrder is the identity for Input); tets are
/// ordered by their vertices when `orderTets`.
Reordering computeReordering(VertexOrdering ordering, const std::vector<Vec3>& points,
  const std::vector<Tet>& tets, const std::vector<std::array<std::int32_t, 2>>& links,
  bool orderTets);

/// out[k] = in[order[k]]: input order -> storage order.
template <typename T>
std::vector<T> toStorageOrder(const std::vector<T>& in, const Order& order)
{
  if (in.empty() || order.empty())
  {
    return in;
  }
  std::vector<T> out(order.size());
  for (std::size_t k = 0; k < order.size(); ++k)
  {
    out[k] = in[static_cast<std::size_t>(order[k])];
  }
  return out;
}

/// out[order[k]] = in[k]: storage order -> input order.
template <typename T>
std::vector<T> toInputOrder(const std::vector<T>& in, const Order& order)
{
  if (in.empty() || order.empty())
  {
    return in;
  }
  std::vector<T> out(order.size());
  for (std::size_t k = 0; k < order.size(); ++k)
  {
    out[static_cast<std::size_t>(order[k])] = in[k];
  }
  return out;
}

/// Tets renumbered to storage vertices and stored in the reordering's tet order.
std::vector<Tet> reorderTets(const std::vector<Tet>& tets, const Reordering& reordering);

/// A stepper built on a reordered body, seen in the input's order: state(), positions(),
/// velocities(), restPositions(), inverseMasses() and tetVolumeRatios() are in input order, and
/// restoreState() takes a snapshot in input order. Link history (DynamicState's link arrays)
/// passes through unchanged: it is indexed by links, which are not reordered here.
class ReorderedSimulation final : public Simulation
{
public:
  /// `warnings`: what to report instead of the stepper's own warnings (those it gives in
  /// input terms); empty: the stepper's.
  ReorderedSimulation(std::unique_ptr<Simulation> inner, Reordering reordering,
    std::vector<std::string> warnings = {});

  AdvanceStatus advance(double endTime, const ProgressCallback& progress = {}) override;
  const DynamicState& state() const override;
  void restoreState(const DynamicState& snapshot) override;

  const std::vector<Vec3>& restPositions() const override { return Rest; }
  const std::vector<double>& inverseMasses() const override { return InverseMass; }
  double totalMass() const override { return Inner->totalMass(); }
  std::vector<double> tetVolumeRatios() const override;
  TetStressField stressField() const override;
  ConditionReadout conditionReadout() const override;
  bool setConditionValues(const std::vector<Condition>& conditions) override;
  double elasticEnergy() const override { return Inner->elasticEnergy(); }
  double stepSize() const override { return Inner->stepSize(); }
  double estimatedStableStep() const override { return Inner->estimatedStableStep(); }
  std::string longRunWarning(double duration) const override
  {
    return Inner->longRunWarning(duration);
  }
  const std::vector<std::string>& warnings() const override
  {
    return Warnings.empty() ? Inner->warnings() : Warnings;
  }
  const StepPlan& stepPlan() const override { return Inner->stepPlan(); }
  const StepControlReport* stepControlReport() const override { return Inner->stepControlReport(); }
  /// Obstacles are in world coordinates, so they pass through unchanged (the stepper's
  /// contacts are in its own numbering and never leave it).
  bool supportsObstacles() const override { return Inner->supportsObstacles(); }
  void setObstacles(std::vector<ObstacleSurface> obstacles, double endTime) override
  {
    Inner->setObstacles(std::move(obstacles), endTime);
  }

  /// The stepper in storage order (its indices are storage indices).
  Simulation& inner() { return *Inner; }
  const Simulation& inner() const { return *Inner; }
  const Reordering& reordering() const { return Map; }

private:
  std::unique_ptr<Simulation> Inner;
  Reordering Map;
  std::vector<std::string> Warnings;
  std::vector<Vec3> Rest;
  std::vector<double> InverseMass;
  mutable DynamicState Out;   ///< the inner state in input order
  mutable bool Stale = true;  ///< Out must be rebuilt before it is read
};

} // namespace softbody
