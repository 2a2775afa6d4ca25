// What the collision detector sees of a mass-spring tet body, and where its floor holds it:
// shared by the CPU stepper, the GPU stepper's floor pass and the set-up's pre-stabilization.
#pragma once

#include "softbody/collision/collision_detector.h"
#include "softbody/scene/scene.h"
#include "softbody/mesh/tet_mesh.h"

#include <cstddef>
#include <string>
#include <vector>

namespace softbody
{

/// Connected body of every point (points in no tet get their own numbers after the bodies);
/// `bodies` is set to how many there are.
std::vector<std::int32_t> bodyOfPoints(const TetMesh& mesh, std::int32_t& bodies);

/// The detector's geometry of a tet body: its boundary triangles (outward) and each point's
/// connected body; every point collides, or only the surface vertices with self-collision.
CollisionGeometry tetBodyGeometry(const TetMesh& mesh, const CollisionSettings& collisions);

/// The floor as the explicit integrators' contacts meet it (CollisionDetector's floor
/// candidates, then respondToContacts): what a stepper that resolves the floor alone, in its
/// own pass (the GPU's), needs to give the same contacts. Tet bodies have no particle radii, so
/// every point's contact thickness is the collision margin.
struct FloorContact
{
  FloorPlane plane;       ///< the detector's floor (its normal normalized again, as it does)
  double thickness = 0.0; ///< C = n . (x - plane) - thickness >= 0 [m]
};

/// The floor contact of `mesh` in `scene` (its margin automatic or given). Throws
/// InvalidInputError for bad collision settings, as the detector does.
FloorContact floorContactOf(const TetMesh& mesh, const Scene& scene);

/// Pre-stabilization (Macklin et al. 2014, initial penetration): each connected body with a
/// point below `plane` is lifted rigidly along its normal by its deepest penetration, so it
/// starts on the plane at rest. Projecting the points one by one in the first step instead
/// crushes the bottom layer and throws the body up (a stiff block placed on the floor, within
/// the contact margin, goes 10 cm up). Bodies with pinned points (inverse mass 0) stay where
/// they are and are pushed onto the plane by the contacts. Returns the bodies lifted.
std::size_t liftBodiesOntoPlane(const TetMesh& mesh, const std::vector<double>& inverseMass,
  const FloorPlane& plane, std::vector<Vec3>& positions);

} // namespace softbody
