// One detected contact: a body point against an obstacle, another particle, or a body triangle.
// Detection (collision_detector.h) produces these; every method's response consumes them.
#pragma once

#include "softbody/common/geometry.h"

#include <array>
#include <cstdint>
#include <vector>

namespace softbody
{

enum class ContactKind : std::uint8_t
{
  Obstacle,     ///< point against an obstacle surface or the floor (a moving plane locally)
  PointPoint,   ///< two particles as spheres (particle bodies)
  PointTriangle ///< a surface vertex against a surface triangle of a body (another or itself)
};

/// The inequality constraint C >= 0 of a contact, linearized where it was detected:
/// - Obstacle:      C = normal . (x_point - surfacePoint(t)) - thickness
/// - PointPoint:    C = |x_point - x_other0| - thickness
/// - PointTriangle: C = normal . (x_point - sum_k barycentric_k x_other_k) - thickness
struct Contact
{
  ContactKind kind = ContactKind::Obstacle;
  std::int32_t point = -1; ///< the body point in contact
  /// PointPoint: other[0] is the other particle (each pair once: `point` is the smaller
  /// index); PointTriangle: the triangle's three points; Obstacle: other[0] is the triangle's
  /// index in its obstacle (-1 for the floor).
  std::array<std::int32_t, 3> other{ -1, -1, -1 };
  Vec3 barycentric = Vec3::Zero(); ///< PointTriangle, Obstacle triangle: weights of the closest point
  /// Unit normal pointing from what is touched toward `point` (Obstacle: the surface's free
  /// side at the closest feature; PointTriangle: the triangle's outward normal, or the
  /// direction from the closest point when the vertex is at an edge or corner).
  Vec3 normal = Vec3::UnitZ();
  /// Obstacle: the closest point at the end of the detected substep (time + h) [m];
  /// PointPoint: the other particle's predicted centre (diagnostics).
  Vec3 surfacePoint = Vec3::Zero();
  Vec3 surfaceVelocity = Vec3::Zero(); ///< Obstacle: its velocity there [m/s]
  double thickness = 0.0; ///< required separation [m] (margin, plus the particle radii)
  /// Index of the obstacle (0-based in setObstacles order; -1 for the floor) for Obstacle
  /// contacts, the other body for PointPoint/PointTriangle (diagnostics, tests).
  std::int32_t source = -1;
};

/// Contacts of one detection pass, sorted by (point, kind, other) so the solve order and
/// therefore the result do not depend on the broad phase or the thread count.
using ContactSet = std::vector<Contact>;

} // namespace softbody
