// Bodies, obstacles and geometric checks of the PBD/XPBD collision tests.
#pragma once

#include "softbody/collision/boundary_triangles.h"
#include "softbody/collision/obstacle.h"
#include "softbody/mesh/mesh_generators.h"
#include "softbody/pbd/pbd_simulation.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace softbody::test
{

/// An n x n x n block of particles (spacing `spacing`, total mass `mass`) held by links to all
/// 26 neighbours, as a voxelized lattice with shear links: a particle body (no tets).
inline Body particleBlock(int n, double spacing, const Vec3& origin, double mass = 1.0)
{
  Body body;
  auto index = [n](int i, int j, int k) { return static_cast<std::int32_t>((k * n + j) * n + i); };
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        body.mesh.points.push_back(origin + spacing * Vec3(i, j, k));
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (int dk = -1; dk <= 1; ++dk)
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di)
            {
              const int a = i + di, b = j + dj, c = k + dk;
              if (a < 0 || b < 0 || c < 0 || a >= n || b >= n || c >= n)
                continue;
              if (index(a, b, c) > index(i, j, k))
                body.links.push_back({ index(i, j, k), index(a, b, c) });
            }
  body.pointMass.assign(body.mesh.points.size(), mass / static_cast<double>(body.mesh.points.size()));
  return body;
}

/// Appends `part` to `body` as another connected component.
inline void appendBody(Body& body, const Body& part)
{
  const auto offset = static_cast<std::int32_t>(body.mesh.points.size());
  body.mesh.points.insert(body.mesh.points.end(), part.mesh.points.begin(), part.mesh.points.end());
  for (Tet t : part.mesh.tets)
  {
    for (std::int32_t& v : t)
      v += offset;
    body.mesh.tets.push_back(t);
  }
  for (auto l : part.links)
    body.links.push_back({ l[0] + offset, l[1] + offset });
  body.pointMass.insert(body.pointMass.end(), part.pointMass.begin(), part.pointMass.end());
}

/// A flat quad obstacle centred at `centre`, spanning +-halfU along u and +-halfV along v, its
/// free side toward u x v.
inline ObstacleSurface quadObstacle(const Vec3& centre, const Vec3& u, const Vec3& v)
{
  ObstacleSurface quad;
  quad.vertices = { centre - u - v, centre + u - v, centre + u + v, centre - u + v };
  quad.triangles = { { 0, 1, 2 }, { 0, 2, 3 } };
  return quad;
}

/// A closed UV sphere, triangles counter-clockwise seen from outside.
inline ObstacleSurface sphereObstacle(const Vec3& centre, double radius, int rings = 12, int sectors = 24)
{
  ObstacleSurface sphere;
  sphere.vertices.push_back(centre + Vec3(0, 0, radius));
  for (int r = 1; r < rings; ++r)
  {
    const double theta = M_PI * r / rings;
    for (int s = 0; s < sectors; ++s)
    {
      const double phi = 2.0 * M_PI * s / sectors;
      sphere.vertices.push_back(centre + radius * Vec3(std::sin(theta) * std::cos(phi),
                                           std::sin(theta) * std::sin(phi), std::cos(theta)));
    }
  }
  sphere.vertices.push_back(centre - Vec3(0, 0, radius));
  const auto ring = [sectors](int r, int s) { return 1 + (r - 1) * sectors + (s % sectors); };
  const int south = static_cast<int>(sphere.vertices.size()) - 1;
  for (int s = 0; s < sectors; ++s)
  {
    sphere.triangles.push_back({ 0, ring(1, s), ring(1, s + 1) });
    for (int r = 1; r + 1 < rings; ++r)
    {
      sphere.triangles.push_back({ ring(r, s), ring(r + 1, s), ring(r + 1, s + 1) });
      sphere.triangles.push_back({ ring(r, s), ring(r + 1, s + 1), ring(r, s + 1) });
    }
    sphere.triangles.push_back({ ring(rings - 1, s), south, ring(rings - 1, s + 1) });
  }
  return sphere;
}

/// Whether segment p-q passes through the interior of triangle a-b-c (Moeller-Trumbore).
inline bool segmentCrossesTriangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c)
{
  const Vec3 d = q - p, e1 = b - a, e2 = c - a;
  const Vec3 h = d.cross(e2);
  const double det = e1.dot(h);
  if (std::abs(det) < 1e-18)
    return false;
  const Vec3 s = p - a;
  const double u = s.dot(h) / det;
  const Vec3 qv = s.cross(e1);
  const double v = d.dot(qv) / det;
  const double t = e2.dot(qv) / det;
  return u > 0.0 && v > 0.0 && u + v < 1.0 && t > 0.0 && t < 1.0;
}

using Triangles = std::vector<std::array<std::int32_t, 3>>;

/// Pairs (one triangle of `A` over points `x`, one of `B` over points `y`) whose surfaces cross:
/// an edge of one passes through the other. Pairs sharing a vertex are skipped when
/// `sameMesh` (neighbours touch by construction).
inline std::size_t crossingTriangles(const Triangles& A, const std::vector<Vec3>& x,
  const Triangles& B, const std::vector<Vec3>& y, bool sameMesh)
{
  std::size_t crossings = 0;
  for (std::size_t i = 0; i < A.size(); ++i)
  {
    for (std::size_t j = sameMesh ? i + 1 : 0; j < B.size(); ++j)
    {
      const auto& s = A[i];
      const auto& t = B[j];
      if (sameMesh)
      {
        bool shared = false;
        for (std::int32_t a : s)
          for (std::int32_t b : t)
            shared = shared || a == b;
        if (shared)
          continue;
      }
      bool crossed = false;
      for (int k = 0; k < 3 && !crossed; ++k)
      {
        crossed = segmentCrossesTriangle(x[s[k]], x[s[(k + 1) % 3]], y[t[0]], y[t[1]], y[t[2]]) ||
          segmentCrossesTriangle(y[t[k]], y[t[(k + 1) % 3]], x[s[0]], x[s[1]], x[s[2]]);
      }
      crossings += crossed ? 1 : 0;
    }
  }
  return crossings;
}

} // namespace softbody::test
