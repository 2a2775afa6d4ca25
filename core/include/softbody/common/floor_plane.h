// The floor plane every method collides with.
#pragma once

#include "softbody/common/geometry.h"

namespace softbody
{

/// A floor: the half-space (x - origin) . normal >= 0 is free space.
struct FloorPlane
{
  Vec3 origin{ 0.0, 0.0, 0.0 };
  Vec3 normal{ 0.0, 0.0, 1.0 }; ///< unit length (normalized by the simulation)
  bool operator==(const FloorPlane&) const = default;
};

} // namespace softbody
