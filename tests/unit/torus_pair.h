// Two TetGen tori stacked along z, the upper one placed `overlap` metres into the lower one
// (a placement mistake, or nested parts) or resting `overlap` < 0 above it: the
// overlapping-start tests and bench_collision_scenes. The tori are those of data/torus.vtp
// (ring radius 0.20 m, tube radius 0.08 m, tilted 30 degrees about x, a 48 x 24 grid), made
// here so that no file has to be read.
#pragma once

#include "softbody/mesh/tetrahedralize.h"
#include "softbody/scene/body.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace softbody::test
{

/// The tori's ring and tube radii [m] (data/torus.vtp).
constexpr double kTorusRing = 0.20;
constexpr double kTorusTube = 0.08;

/// One tet torus centred at the origin, tilted 30 degrees about x. `maxTetVolume` [m^3] sets
/// the size: 2e-5 gives ~3,000 points.
inline TetMesh tetTorus(double maxTetVolume)
{
  const int nu = 48, nv = 24;
  const double pi = std::acos(-1.0), tilt = 30.0 * pi / 180.0;
  std::vector<Vec3> points;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j)
    {
      const double u = 2 * pi * i / nu, v = 2 * pi * j / nv;
      const Vec3 p((kTorusRing + kTorusTube * std::cos(v)) * std::cos(u),
        (kTorusRing + kTorusTube * std::cos(v)) * std::sin(u), kTorusTube * std::sin(v));
      points.emplace_back(p.x(), std::cos(tilt) * p.y() - std::sin(tilt) * p.z(),
        std::sin(tilt) * p.y() + std::cos(tilt) * p.z());
    }
  auto id = [&](int i, int j) { return ((i % nu) * nv) + (j % nv); };
  std::vector<std::array<std::int32_t, 3>> triangles;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j)
    {
      triangles.push_back({ id(i, j), id(i + 1, j), id(i + 1, j + 1) });
      triangles.push_back({ id(i, j), id(i + 1, j + 1), id(i, j + 1) });
    }
  TetrahedralizeOptions options;
  options.maxTetVolume = maxTetVolume;
  return tetrahedralizeSurface(points, triangles, options);
}

/// The pair as one Body: the lower torus centred at z = 0.5 m, the upper one above it, its
/// lowest point `overlap` metres below the lower torus's highest point (< 0: a gap). Points
/// [0, lowerPoints) are the lower torus's.
struct TorusPair
{
  Body body;
  std::size_t lowerPoints = 0;
};

inline TorusPair torusPair(double overlap, double maxTetVolume = 2e-5)
{
  const TetMesh torus = tetTorus(maxTetVolume);
  double low = 1e9, high = -1e9;
  for (const Vec3& p : torus.points)
  {
    low = std::min(low, p.z());
    high = std::max(high, p.z());
  }
  const Vec3 lower(0.0, 0.0, 0.5), upper(0.0, 0.0, 0.5 + (high - low) - overlap);
  TorusPair pair;
  for (const Vec3& centre : { lower, upper })
  {
    const auto offset = static_cast<std::int32_t>(pair.body.mesh.points.size());
    for (const Vec3& p : torus.points)
    {
      pair.body.mesh.points.push_back(p + centre);
    }
    for (Tet t : torus.tets)
    {
      for (std::int32_t& v : t)
        v += offset;
      pair.body.mesh.tets.push_back(t);
    }
  }
  pair.lowerPoints = torus.points.size();
  return pair;
}

} // namespace softbody::test
