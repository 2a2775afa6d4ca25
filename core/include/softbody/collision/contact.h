// One detected contact: a body point against an obstacle, another particle, or a body triangle,
// or an edge of a body surface against another edge.
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
  PointTriangle, ///< a surface vertex against a surface triangle of a body (another or itself)
  /// an edge of a body surface against an edge of another (or of itself) where the closest
  /// points are inside both edges: two bars crossed at right angles touch this way, with no
  /// vertex near a face
  EdgeEdge
};

/// The inequality constraint C >= 0 of a contact, linearized where it was detected:
/// - Obstacle:      C = normal . (x_point - surfacePoint(t)) - thickness
/// - PointPoint:    C = |x_point - x_other0| - thickness
/// - PointTriangle: C = normal . (x_point - sum_k barycentric_k x_other_k) - thickness
/// - EdgeEdge:      C = normal . ((1 - s) x_point + s x_other0 - (1 - t) x_other1 - t x_other2)
///                  - thickness, with (s, t) = barycentric[0], [1]
struct Contact
{
  ContactKind kind = ContactKind::Obstacle;
  std::int32_t point = -1; ///< the body point in contact
  /// PointPoint: other[0] is the other particle (each pair once: `point` is the smaller
  /// index); PointTriangle: the triangle's three points; Obstacle: other[0] is the triangle's
  /// index in its obstacle (-1 for the floor); EdgeEdge: other[0] is the far end of the edge
  /// that starts at `point`, other[1], other[2] the other edge (each pair of edges once).
  std::array<std::int32_t, 3> other{ -1, -1, -1 };
  /// PointTriangle, Obstacle triangle: weights of the closest point; EdgeEdge: (s, t, 0), the
  /// weights of other[0] on the first edge and of other[2] on the second.
  Vec3 barycentric = Vec3::Zero();
  /// Unit normal pointing from what is touched toward `point` (Obstacle: the surface's free
  /// side at the closest feature; PointTriangle: the triangle's outward normal, or the
  /// direction from the closest point when the vertex is at an edge or corner; EdgeEdge: from
  /// the second edge's closest point toward the first's at the start of the substep).
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

/// Contacts of one detection pass, sorted by (point, kind, source, other) so the solve order and
/// therefore the result do not depend on the broad phase or the thread count; per point, the
/// obstacle contacts come first.
using ContactSet = std::vector<Contact>;

/// Sets mask[i] for every body point a contact involves (an obstacle contact's own point only:
/// its other[] indexes the obstacle).
inline void markContactPoints(const ContactSet& contacts, std::vector<char>& mask)
{
  for (const Contact& c : contacts)
  {
    mask[static_cast<std::size_t>(c.point)] = 1;
    for (std::int32_t other : c.other)
    {
      if (c.kind != ContactKind::Obstacle && other >= 0)
      {
        mask[static_cast<std::size_t>(other)] = 1;
      }
    }
  }
}

} // namespace softbody
