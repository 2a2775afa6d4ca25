// The mass-spring floor: a position and velocity correction applied after each step.
#pragma once

#include "softbody/common/floor_plane.h"

#include <vector>

namespace softbody
{

/// Projects penetrating points onto the plane and cancels their velocity into it (a perfectly
/// inelastic, frictionless contact). Pinned points (inverse mass 0) are left alone.
/// Returns the number of points projected.
std::size_t resolveFloorContacts(const FloorPlane& floor, const std::vector<double>& inverseMass,
  std::vector<Vec3>& positions, std::vector<Vec3>& velocities);

} // namespace softbody
