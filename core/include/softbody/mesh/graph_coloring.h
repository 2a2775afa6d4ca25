// Graph coloring of a constraint batch: constraints that share a particle get different colors,
// so all constraints of one color can be projected in parallel without two threads writing the
// same particle; and of a mesh's points, for per-point Gauss-Seidel. This is what makes parallel Gauss-Seidel race-free and its result independent
// of the number of threads.
#pragma once

#include "softbody/mesh/topology.h" // Csr

#include <cstdint>
#include <vector>

namespace softbody
{

struct Coloring
{
  std::vector<std::int32_t> order;        ///< constraint indices grouped by color
  std::vector<std::int32_t> colorOffsets; ///< color k is order[colorOffsets[k] .. colorOffsets[k+1])
  std::size_t colorCount() const { return colorOffsets.empty() ? 0 : colorOffsets.size() - 1; }
};

/// Particle -> constraint slots (c * arity + k) of a batch whose constraint c touches
/// particles[c * arity .. c * arity + arity).
Csr particleSlots(std::size_t particleCount, const std::vector<std::int32_t>& particles);

/// Greedy coloring in constraint order (deterministic): each constraint takes the smallest color
/// none of its particles' earlier constraints has. Particles with inverse mass 0 never move, so
/// they do not link constraints (`movable[i] == 0` skips particle i); that keeps pinned hubs
/// from forcing extra colors.
Coloring colorConstraints(std::size_t particleCount, const std::vector<std::int32_t>& particles,
  int arity, const std::vector<char>& movable);

/// Greedy coloring of a mesh's points in index order (deterministic): points joined by an edge
/// (two corners of one element) get different colors, so the points of one color can be
/// updated in parallel, each reading only points of other colors (Vertex Block Descent).
Coloring colorVertices(const Topology& topology);

} // namespace softbody
