// An obstacle: a triangulated surface the bodies collide with, static or moving.
#pragma once

#include "softbody/common/geometry.h"

#include <array>
#include <cstdint>
#include <vector>

namespace softbody
{

/// A triangle surface, one-sided: the free side is the one its triangles' normals
/// (b - a) x (c - a) point to (counter-clockwise seen from outside), so a closed surface
/// pushes bodies out and an open one (a ramp, a bowl) pushes them to its normal side.
struct ObstacleSurface
{
  /// Positions at the end of the coming advance() [m].
  std::vector<Vec3> vertices;
  /// Empty for a static obstacle; otherwise one velocity per vertex [m/s], constant during
  /// the coming advance(): at time t the vertex is at vertices[i] + (t - endTime) velocities[i].
  /// Friction and restitution act on the velocity relative to it.
  std::vector<Vec3> velocities;
  std::vector<std::array<std::int32_t, 3>> triangles;
  bool operator==(const ObstacleSurface&) const = default;
};

} // namespace softbody
