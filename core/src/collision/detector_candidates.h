// One point's (or one edge's) narrow-phase results inside CollisionDetector: shared by the
// point pass (collision_detector.cpp) and the edge pass (collision_detector_edges.cpp).
#pragma once

#include "softbody/collision/collision_detector.h"
#include "softbody/collision/narrow_phase.h"

#include <cstdint>
#include <vector>

namespace softbody
{

struct CollisionDetector::Candidates
{
  std::vector<ContactCandidate> found;
  std::vector<std::uint32_t> order; ///< scratch of reduceCandidates
  std::vector<std::uint32_t> kept;
  std::size_t examined = 0; ///< pairs the narrow phase looked at
};

} // namespace softbody
