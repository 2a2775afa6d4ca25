#include "softbody/collision/closest_point.h"

#include <algorithm>

namespace softbody
{

double closestPointOnSegment(const Vec3& p, const Vec3& a, const Vec3& b)
{
  const Vec3 ab = b - a;
  const double length2 = ab.squaredNorm();
  if (!(length2 > 0.0))
  {
    return 0.0; // a point: both ends are the same
  }
  return std::clamp((p - a).dot(ab) / length2, 0.0, 1.0);
}

SegmentPair closestPointsOfSegments(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1)
{
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  SegmentPair pair;
  if (!(a > 0.0) && !(e > 0.0))
  {
    return pair; // two points
  }
  if (!(a > 0.0))
  {
    pair.t = std::clamp(f / e, 0.0, 1.0);
    return pair;
  }
  const double c = d1.dot(r);
  if (!(e > 0.0))
  {
    pair.s = std::clamp(-c / a, 0.0, 1.0);
    return pair;
  }
  const double b = d1.dot(d2);
  const double denominator = a * e - b * b; // >= 0; 0 for parallel segments
  pair.s = denominator > 0.0 ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
  pair.t = (b * pair.s + f) / e;
  if (pair.t < 0.0)
  {
    pair.t = 0.0;
    pair.s = std::clamp(-c / a, 0.0, 1.0);
  }
  else if (pair.t > 1.0)
  {
    pair.t = 1.0;
    pair.s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  return pair;
}

namespace
{

TrianglePoint onEdge(const Vec3& a, const Vec3& b, double t, int from, int to, TriangleFeature edge,
  TriangleFeature vertexFrom, TriangleFeature vertexTo)
{
  TrianglePoint result;
  result.point = a + t * (b - a);
  result.barycentric[from] = 1.0 - t;
  result.barycentric[to] += t;
  result.feature = t <= 0.0 ? vertexFrom : (t >= 1.0 ? vertexTo : edge);
  return result;
}

/// The zero-area case: the nearest of the three edges (ties to the first).
TrianglePoint closestOnDegenerate(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c)
{
  using F = TriangleFeature;
  const TrianglePoint candidates[3] = {
    onEdge(a, b, closestPointOnSegment(p, a, b), 0, 1, F::EdgeAB, F::VertexA, F::VertexB),
    onEdge(b, c, closestPointOnSegment(p, b, c), 1, 2, F::EdgeBC, F::VertexB, F::VertexC),
    onEdge(c, a, closestPointOnSegment(p, c, a), 2, 0, F::EdgeCA, F::VertexC, F::VertexA)
  };
  int best = 0;
  for (int k = 1; k < 3; ++k)
  {
    if ((candidates[k].point - p).squaredNorm() < (candidates[best].point - p).squaredNorm())
    {
      best = k;
    }
  }
  return candidates[best];
}

} // namespace

TrianglePoint closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c)
{
  // Ericson's ClosestPtPointTriangle (5.1.5), region by region.
  TrianglePoint result;
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0)
  {
    result.point = a;
    result.barycentric = Vec3(1, 0, 0);
    result.feature = TriangleFeature::VertexA;
    return result;
  }
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3)
  {
    result.point = b;
    result.barycentric = Vec3(0, 1, 0);
    result.feature = TriangleFeature::VertexB;
    return result;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0)
  {
    const double v = d1 / (d1 - d3);
    result.point = a + v * ab;
    result.barycentric = Vec3(1 - v, v, 0);
    result.feature = TriangleFeature::EdgeAB;
    return result;
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6)
  {
    result.point = c;
    result.barycentric = Vec3(0, 0, 1);
    result.feature = TriangleFeature::VertexC;
    return result;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0)
  {
    const double w = d2 / (d2 - d6);
    result.point = a + w * ac;
    result.barycentric = Vec3(1 - w, 0, w);
    result.feature = TriangleFeature::EdgeCA;
    return result;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
  {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    result.point = b + w * (c - b);
    result.barycentric = Vec3(0, 1 - w, w);
    result.feature = TriangleFeature::EdgeBC;
    return result;
  }
  // va + vb + vc is |ab x ac|^2: zero for a degenerate triangle, whose "face" has no interior.
  const double sum = va + vb + vc;
  if (!(sum > 1e-300) || !(sum > 1e-24 * ab.squaredNorm() * ac.squaredNorm()))
  {
    return closestOnDegenerate(p, a, b, c);
  }
  const double v = vb / sum, w = vc / sum;
  result.point = a + v * ab + w * ac;
  result.barycentric = Vec3(1 - v - w, v, w);
  result.feature = TriangleFeature::Face;
  return result;
}

} // namespace softbody
