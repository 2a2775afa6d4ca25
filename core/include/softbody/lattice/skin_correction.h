// Render corrections of a skinned surface against what the body touches (the floor and the
// obstacles). The particles are kept out by the contacts, but a skinned vertex bound by
// extrapolation (outside its cell or tet, as the surface of a voxelized body is) or inside a
// cell that a contact squashes or tilts is not a convex combination of them and can end up
// inside what they rest on (voxelized spot: 12 cm below the floor). Only the drawn surface is
// corrected; the body is not.
#pragma once

#include "softbody/collision/obstacle.h"
#include "softbody/common/floor_plane.h"
#include "softbody/common/geometry.h"
#include "softbody/lattice/skinning.h"

#include <cstddef>
#include <vector>

namespace softbody
{

/// What a correction did: how many vertices it moved and the longest move [m] (how deep the
/// deepest one was: without the correction it would be drawn that far inside).
struct SkinCorrection
{
  std::size_t moved = 0;
  double deepest = 0.0;
};

/// Moves every vertex below the floor onto it along the normal.
SkinCorrection keepAboveFloor(const FloorPlane& floor, std::vector<Vec3>& vertices);

/// How far each skinned vertex may lie behind a surface its particles are kept in front of:
/// the distance to its farthest bound particle (current positions). A vertex deeper than that
/// behind a one-sided surface is taken to be on its other side (behind a thin wall), as the
/// narrow phase takes a point deeper than its query radius.
std::vector<double> skinReach(const Skin& skin, const std::vector<Vec3>& particlePositions,
  const std::vector<Vec3>& vertices);

/// Moves every vertex that lies on the inner side of an obstacle, within reach[v] of it, onto
/// its surface: the closest triangle (a BVH over all obstacles' triangles; the narrow phase's
/// one-sided rules: behind a triangle only where the vertex projects onto its face) decides,
/// and when the vertex is behind it, it goes to the closest point, along the face normal.
/// Obstacle `vertices` are taken as they are (the frame's time); velocities are ignored.
/// Parallel over vertices, each written by one task: the same result at any thread count.
SkinCorrection keepOutsideObstacles(const std::vector<ObstacleSurface>& obstacles,
  const std::vector<double>& reach, std::vector<Vec3>& vertices);

} // namespace softbody
