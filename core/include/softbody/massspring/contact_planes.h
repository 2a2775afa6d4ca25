// The planes an implicit step keeps each point on the free side of: the floor, and the obstacle
// face each point is heading for in the step. The implicit solve (implicit_solve.h) treats them
// as one active set: a point that reaches its plane is held on it and slides along it, so
// obstacles hold inside the minimization as the floor does, and the rest of the body answers
// the contact in the same step instead of being crushed by a projection after it.
//
// One plane per point, linearized at the step's start: the obstacle face a point would reach is
// found by the swept detector (collision_detector.h) from its start to the step's explicit
// prediction, and replaced by its tangent plane at the closest point, lifted by the contact's
// thickness (the margin). A flat obstacle (a ramp, a wall, a box face) is then exact; on a
// curved one the tangent plane is off by the curvature over the point's slip in one step (outside
// a convex obstacle, so it never lets a point in; inside a concave one by at most that much,
// which the contact response after the step removes). A point near two faces (a crease, the
// ramp's foot on the floor) keeps the one its prediction lies deepest behind.
#pragma once

#include "softbody/collision/contact.h"
#include "softbody/common/floor_plane.h"
#include "softbody/common/geometry.h"
#include "softbody/mesh/topology.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

namespace softbody
{

/// The free side is (x - origin) . normal >= 0; `velocity` is the surface's, for friction.
/// A plane standing for another body's face also names that face's corners and the point's
/// barycentric weights on it: the push that holds the point is that body's load (Newton's third
/// law), which the implicit solve carries over to it (implicit_solve.cpp).
struct ContactPlane
{
  Vec3 origin = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ(); ///< unit length
  Vec3 velocity = Vec3::Zero(); ///< [m/s]
  std::array<std::int32_t, 3> corners{ -1, -1, -1 }; ///< the other body's face; -1: none
  Vec3 weights = Vec3::Zero();
  Vec3 lift = Vec3::Zero(); ///< origin minus the face's point (the contact's thickness along normal)
  bool onBody() const { return corners[0] >= 0; }
};

class ContactPlanes
{
public:
  /// `floor`: the plane every point is held above (already lifted by the contact margin), or
  /// none.
  explicit ContactPlanes(std::optional<FloorPlane> floor = std::nullopt);

  /// Every one of `pointCount` points gets the floor (or no plane); obstacle planes are gone.
  void reset(std::size_t pointCount);
  /// Adds the planes of the Obstacle and PointTriangle contacts of `detected` (the detector's
  /// contacts of the sweep from `start` to `predicted`; edge contacts are left to the response
  /// after the step): a point keeps, of its planes and the floor, the one `predicted` lies
  /// deepest behind (or least in front of). An obstacle's plane is its face where it is at the
  /// step's end; another body's face is where its own prediction puts it, moving at its corners'
  /// start `velocities` (friction is relative to that): bodies falling together keep their
  /// places, and a body landing on another stops on it in the solve instead of being projected
  /// out of it after the step. A point that starts behind a face is reached from the wrong side
  /// (the underside of a thin plate it crossed, a body placed inside another): such faces count
  /// only when the point starts behind all of its faces (the nearest one pushes it out), as in
  /// the contact response.
  void addContacts(const ContactSet& detected, const std::vector<Vec3>& start, const std::vector<Vec3>& predicted,
    const std::vector<Vec3>& velocities);

  /// Per point, the size of its elements [m] (pointElementSizes): how far friction may move
  /// it after the solve (implicit_solve.cpp); none given: 0 for all, no bound.
  void setElementSizes(std::vector<double> sizes) { ElementSizes = std::move(sizes); }
  double elementSize(std::size_t i) const { return ElementSizes.empty() ? 0.0 : ElementSizes[i]; }

  bool empty() const { return Planes.empty(); }
  std::size_t pointCount() const { return PlaneOf.size(); }
  bool has(std::size_t i) const { return PlaneOf[i] >= 0; }
  /// Point i's plane (has(i) must hold).
  const ContactPlane& of(std::size_t i) const { return Planes[static_cast<std::size_t>(PlaneOf[i])]; }
  /// Moves every plane that stands for another body's face to where `x` has that face.
  void followBodies(const std::vector<Vec3>& x);
  /// Signed distance of x to point i's plane [m]; +infinity when it has none.
  double depth(std::size_t i, const Vec3& x) const;

private:
  std::optional<FloorPlane> Floor;
  std::vector<ContactPlane> Planes; ///< the floor first (when there is one), then obstacle faces
  std::vector<std::int32_t> PlaneOf; ///< per point, its plane in Planes; -1 for none
  std::vector<double> ElementSizes;
};

/// The point that moves furthest into its plane in a step of h from (x0, v0), relative to its
/// elements' size: how far x0 + h v0 lies deeper behind its plane than x0 does [m].
struct ContactApproach
{
  double approach = 0.0; ///< [m]
  double size = 0.0;     ///< that point's element size [m]
  double ratio() const { return size > 0.0 ? approach / size : 0.0; }
  /// More than a step may take (kContactApproachFraction).
  bool tooFast() const;
};

/// The most an implicit step may move a point into its contact plane, as a fraction of its
/// elements' size: the step stops the point there while the points behind it move on, and the
/// elements between have to take the difference. Two TetGen tori (3.2 cm elements) landing on
/// the floor and on each other at 2.5-3.7 m/s, in automatic steps split to this fraction
/// (MassSpringSimulation::contactPieces), kept at most 5 of 7,888 tets inverted in a frame at 1,
/// and 1 at 0.5 (Implicit Euler, spring network; Euler-Cromer at its stable step: 1); 0.25 took
/// twice the steps for no fewer.
constexpr double kContactApproachFraction = 0.5;
inline bool ContactApproach::tooFast() const { return ratio() > kContactApproachFraction; }
ContactApproach fastestApproach(const ContactPlanes& planes, const std::vector<Vec3>& x0,
  const std::vector<Vec3>& v0, const std::vector<double>& inverseMass, double h);

/// Ahead of a run: the body that will land on `floor` fastest relative to its elements, and
/// how far its landing speed carries it in a step of h. Each body (bodyOf, `bodies` of them)
/// lands with its lowest free point, falling from x0 with v0 under `gravity`: at
/// sqrt(v_n^2 + 2 g_n d) from height d. A landing step longer than the elements' size over that
/// speed crushes the elements where the body lands. Bodies resting on the plane, held points and
/// bodies that never reach it are left out.
struct LandingApproach
{
  ContactApproach approach; ///< the landing step's approach [m] and the lowest point's element size
  double speed = 0.0;       ///< at the floor [m/s]
  double height = 0.0;      ///< fallen [m]
};
LandingApproach floorLandingApproach(const ContactPlanes& planes, const FloorPlane& floor, const Vec3& gravity,
  const std::vector<Vec3>& x0, const std::vector<Vec3>& v0, const std::vector<double>& inverseMass,
  const std::vector<std::int32_t>& bodyOf, std::int32_t bodies, double h);

/// Per point, the mean rest length of its edges [m] (0 for a point without edges).
std::vector<double> pointElementSizes(const Topology& topology, const std::vector<Vec3>& rest);

} // namespace softbody
