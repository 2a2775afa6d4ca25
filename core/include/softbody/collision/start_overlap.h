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

/// Points of body `body` that start behind obstacle `obstacle`'s surface: behind the face
/// nearest to them (its normal pointing away), where the face's interior is what is nearest.
struct ObstacleStartOverlap
{
  std::int32_t body = -1;
  std::int32_t obstacle = -1; ///< 0-based in setObstacles order
  std::size_t behind = 0;     ///< colliding points behind the surface
  std::size_t inFront = 0;    ///< colliding points in front of its faces
  double depth = 0.0;         ///< the deepest behind [m]
  bool closed = false;        ///< every edge of the obstacle has two faces
};

/// The bodies that start across an obstacle (some points behind its surface, some in front),
/// or inside a closed one: a one-sided surface pushes the shallow points out and lets the deep
/// ones through from behind, pulling the body across it. Sorted by (body, obstacle); bodies
/// wholly behind an open surface (a body under a ramp) are not listed.
std::vector<ObstacleStartOverlap> findObstacleStartOverlaps(const CollisionGeometry& geometry,
  const std::vector<Vec3>& positions, const std::vector<ObstacleSurface>& obstacles);

/// The warning for `overlaps` (empty when there are none): per body and obstacle, how many
/// points start behind it and how deep, and the remedy (move the body to the free side by at
/// least that depth, or reverse the obstacle's sense).
std::string obstacleStartOverlapWarning(const std::vector<ObstacleStartOverlap>& overlaps);

/// Once per run, where it starts (time 0, obstacles set): the warning of the two above for what
/// `detector` collides and its obstacles at `positions`, appended to `warnings`; `checked`
/// remembers that it was done (moving obstacles are set again every frame).
void noteObstacleStart(const CollisionDetector& detector, const std::vector<Vec3>& positions, double time,
  bool& checked, std::vector<std::string>& warnings);

} // namespace softbody
