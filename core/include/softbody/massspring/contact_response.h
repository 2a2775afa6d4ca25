// Mass-spring contact response: after a step, the detected contacts (collision/contact.h) are
// resolved by a position projection and a velocity response, the thesis's treatment of its
// floor extended to every contact (obstacles, the floor, other bodies, the body itself).
#pragma once

#include "softbody/collision/collision_settings.h"
#include "softbody/collision/contact.h"

#include <cstddef>
#include <vector>

namespace softbody
{

/// What one respondToContacts call did (tests, diagnostics).
struct ContactResponseStats
{
  std::size_t projected = 0; ///< contacts that were penetrating (C < 0) and were projected
  std::size_t ignored = 0;   ///< obstacle contacts dropped as reached from behind (see below)
};

/// Resolves the contacts of one step of size h, in place, in the contacts' (sorted) order.
///
/// Each contact is C(x) = n . (sum_j c_j x_j - s) - thickness >= 0 with n its normal and
/// - Obstacle:      c = {1} (the point), s = surfacePoint (the obstacle at the step's end);
/// - PointPoint:    c = {1, -1} (the point, the other particle), s = 0, n from the positions;
/// - PointTriangle: c = {1, -b0, -b1, -b2} (the point, the triangle's corners), s = 0;
/// - EdgeEdge:      c = {1 - s, s, -(1 - t), -t} (the two edges' ends), s = 0 (contact_terms.h).
/// With W = sum_j c_j^2 w_j (w: inverse masses; 0 for pinned points, which never move):
/// 1. Projection: where C < 0, x_j += c_j w_j (-C / W) n: the closest configuration on the
///    constraint, split by inverse mass and barycentric weight (PBD's distance projection);
///    positions only, so a removed penetration adds no velocity.
/// 2. Velocity response, where the contact was penetrating (v_rel = sum_j c_j v_j -
///    surfaceVelocity): an approaching normal speed v_n < 0 becomes -e v_n (restitution e), a
///    change dv_n = (1 + e) |v_n|. Friction acts on the normal push p = max(dv_n, -C / h) (the
///    penetration removed per unit time carries the load where the approach is nil: a body
///    resting on another that falls with it): the tangential relative velocity v_t sticks (is
///    cancelled, and so is this step's tangential slip of the positions) while
///    |v_t| <= staticFriction p, and otherwise slides, losing dynamicFriction p of its speed
///    (Coulomb). Both are impulses J split like the projection: v_j += c_j w_j J / W.
/// On a plane under gravity g at angle theta this gives a sliding acceleration of
/// g (sin theta - mu_d cos theta) and sticking while tan theta <= mu_s (e = 0).
///
/// Tunnelling: detection is swept (collision_detector.h), so a point that crossed a thin
/// obstacle within the step is found behind the face it crossed and pushed back out of it.
/// It may also be found behind the obstacle's far face (the underside of a thin plate, whose
/// normal points away from it), which would push it on through: of a point's obstacle
/// contacts, those whose plane the point started the step behind are ignored when another one
/// has it starting in front. A point that starts behind all of them (a body created inside an
/// obstacle) keeps them all and is pushed out along their normals.
///
/// `start` holds the positions at the start of the step. Obstacle contacts touch one point
/// each and run in parallel per point; body contacts follow, one after the other, so the
/// result does not depend on the thread count.
ContactResponseStats respondToContacts(const ContactSet& contacts, const CollisionSettings& settings,
  const std::vector<double>& inverseMass, const std::vector<Vec3>& start, double h,
  std::vector<Vec3>& positions, std::vector<Vec3>& velocities);

} // namespace softbody
