// Bodies that start one inside another (a placement mistake, or nested parts): found at set-up
// for the warning, and separated gently by the contacts (collision_detector.cpp limits how
// fast a penetration that a substep starts with is removed).
#pragma once

#include "softbody/collision/collision_detector.h"

#include <cstdint>
#include <string>
#include <vector>

namespace softbody
{

/// The fastest a contact removes a penetration that was already there at the start of its
/// substep [m/s]: bodies started d metres into each other come apart in about
/// d / (0.5 m/s), rather than in one substep at d / h (0.08 m at h = 1/120 s would be
/// 9.6 m/s, and the bodies burst). Contacts made during a substep are resolved in full.
constexpr double kStartOverlapSeparationSpeed = 0.5;

/// Points of body `inner` that lie inside the closed surface of body `outer` (bodies as in
/// CollisionGeometry::bodyOf).
struct StartOverlap
{
  std::int32_t inner = -1;
  std::int32_t outer = -1;
  std::size_t points = 0; ///< colliding points of `inner` inside `outer`
  double depth = 0.0;     ///< the deepest of them: distance to `outer`'s surface [m]
};

/// The overlaps of `positions` (stepper numbering): every colliding point tested against the
/// closed one-sided surfaces (tet bodies' boundaries) of the other bodies, by the parity of a
/// vertical ray's crossings; particles and cloth have no inside and are not tested. Sorted by
/// (inner, outer); deterministic, parallel over the points.
std::vector<StartOverlap> findStartOverlaps(const CollisionGeometry& geometry, const std::vector<Vec3>& positions);

/// The set-up warning for `overlaps` (empty string when there are none): per pair, how many
/// points, the deepest penetration, how long the contacts take to separate them, and the
/// remedy (move the body by at least that depth).
std::string startOverlapWarning(const std::vector<StartOverlap>& overlaps);

} // namespace softbody
