// Checks of what a CollisionDetector is given (geometry, obstacles), each refusal quoting the
// value, and the automatic contact margin.
#pragma once

#include "softbody/collision/collision_detector.h"

namespace softbody
{

/// Sizes consistent, positions finite, radii >= 0, indices in range; InvalidInputError otherwise.
void validateCollisionGeometry(const CollisionGeometry& geometry);

/// Finite vertices and velocities, velocities empty or one per vertex, indices in range, a
/// finite end time; InvalidInputError otherwise.
void validateObstacles(const std::vector<ObstacleSurface>& obstacles, double endTime);

/// CollisionMargin = 0: a tenth of the mean surface edge length where there are surface
/// triangles, a tenth of the mean particle radius where there are particles (the smaller of
/// the two when both), so the gap kept between touching things stays small against the
/// bodies' own scale. (A margin of a whole radius, as first planned, would keep particles
/// two radii off the floor: visibly floating.)
double automaticMargin(const CollisionGeometry& geometry);

} // namespace softbody
