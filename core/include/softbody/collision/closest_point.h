// The closest point of a triangle to a point, with the feature it lies on (face, edge, vertex),
// and the closest points of two segments: the exact narrow phases of point-triangle and
// edge-edge contacts.
#pragma once

#include "softbody/common/geometry.h"

#include <cstdint>

namespace softbody
{

/// Where on the triangle (a, b, c) the closest point lies. The feature decides the contact
/// normal: the face normal inside, the direction from the closest point on an edge or corner.
enum class TriangleFeature : std::uint8_t
{
  Face,
  EdgeAB,
  EdgeBC,
  EdgeCA,
  VertexA,
  VertexB,
  VertexC
};

struct TrianglePoint
{
  Vec3 point = Vec3::Zero();       ///< the closest point [m]
  Vec3 barycentric = Vec3::Zero(); ///< weights of a, b, c (sum 1, all >= 0)
  TriangleFeature feature = TriangleFeature::Face;
};

/// Closest point of triangle (a, b, c) to p, by the Voronoi-region tests of Ericson, Real-Time
/// Collision Detection (2005), 5.1.5: vertex regions first, then edges, else the face; no
/// square root, no projection onto the plane first. A degenerate (zero-area) triangle, where
/// the face weights would divide by zero, returns the closest point of its three edges.
TrianglePoint closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

/// Closest point of the segment [a, b] to p, as the weight t of b (point = a + t (b - a)).
double closestPointOnSegment(const Vec3& p, const Vec3& a, const Vec3& b);

/// The closest points of segments [p0, p1] and [q0, q1], as the weights s of p1 and t of q1
/// (p0 + s (p1 - p0), q0 + t (q1 - q0); both in [0, 1]).
struct SegmentPair
{
  double s = 0.0;
  double t = 0.0;
};

/// Ericson, Real-Time Collision Detection (2005), 5.1.9: the unconstrained minimum of the
/// lines, clamped to the first segment, the second's weight recomputed and clamped, the first
/// recomputed once more. Parallel segments (where the lines' minimum is not unique) take s = 0
/// and the nearest t; a zero-length segment is its point.
SegmentPair closestPointsOfSegments(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1);

} // namespace softbody
