// The closest point of a triangle to a point, with the feature it lies on (face, edge, vertex):
// the exact narrow phase of every point-triangle contact.
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

} // namespace softbody
