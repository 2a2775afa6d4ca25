// The PBD thesis's test object: a rectangular sheet of particles joined by structural links
// (to the neighbors along each grid axis) and by the two diagonals of every grid cell at a
// fraction of the structural stiffness.
#pragma once

#include "softbody/pbd/pbd_simulation.h" // Body

namespace softbody
{

enum class ClothPins
{
  None,
  Point2Corners, ///< the two corners on the Point2 edge (the top, when Point2 is up)
  AllCorners
};

struct ClothSpec
{
  /// The sheet spans origin + s (point1 - origin) + t (point2 - origin), s, t in [0, 1], like
  /// vtkPlaneSource.
  Vec3 origin{ 0.0, 0.0, 0.0 };
  Vec3 point1{ 1.0, 0.0, 0.0 };
  Vec3 point2{ 0.0, 1.0, 0.0 };
  int particlesAlong1 = 50; ///< >= 2
  int particlesAlong2 = 50; ///< >= 2
  double totalMass = 1.0;   ///< [kg], spread equally over the particles
  double diagonalStiffness = 0.01; ///< diagonal links' factor on the link stiffness; 0 = none
  ClothPins pins = ClothPins::None;
};

/// Point (i, j), i along point1 and j along point2, has index j * particlesAlong1 + i. Links:
/// all structural links first (along 1, then along 2), then the diagonals. Its surface
/// triangles (two per cell) are what it collides through.
Body makeCloth(const ClothSpec& spec);

} // namespace softbody
