// Small helpers shared by the unit tests.
#pragma once

#include "softbody/common/errors.h"
#include "softbody/common/geometry.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

namespace softbody::test
{

/// Positions displaced by uniform noise of the given amplitude (deterministic seed).
inline std::vector<Vec3> jitter(std::vector<Vec3> points, double amplitude, unsigned seed = 7)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  for (Vec3& p : points)
  {
    p += Vec3(u(rng), u(rng), u(rng));
  }
  return points;
}

/// ../shared/data (the public meshes), or empty when the build was configured without it;
/// tests skip with a message when it is empty or absent.
/// The message of the InvalidInputError that building a `Simulation` from `args` throws, or ""
/// when it builds.
template <class Simulation, class... Args>
std::string refusalOf(const Args&... args)
{
  try
  {
    Simulation simulation(args...);
  }
  catch (const InvalidInputError& error)
  {
    return error.what();
  }
  return {};
}

inline std::filesystem::path sharedData()
{
#ifdef SOFTBODY_SHARED_DATA_DIR
  return SOFTBODY_SHARED_DATA_DIR;
#else
  return {};
#endif
}

/// Largest |a_i - b_i| [m]: how far two states of the same body are apart.
inline double maxDistance(const std::vector<Vec3>& a, const std::vector<Vec3>& b)
{
  double largest = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    largest = std::max(largest, (a[i] - b[i]).norm());
  }
  return largest;
}

/// Same size and the same bytes.
inline bool bitwiseEqual(const std::vector<Vec3>& a, const std::vector<Vec3>& b)
{
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}

/// Mean of rest.z - now.z over the points whose rest position passes `select` [m]: how far a
/// face of a body (a bar's bottom, a cantilever's tip) has dropped.
template <class Select>
double meanDrop(const std::vector<Vec3>& rest, const std::vector<Vec3>& now, Select&& select)
{
  double drop = 0.0;
  int count = 0;
  for (std::size_t i = 0; i < rest.size(); ++i)
  {
    if (select(rest[i]))
    {
      drop += rest[i].z() - now[i].z();
      ++count;
    }
  }
  return drop / count;
}

/// Flags the points whose position passes `select` (nonzero: pinned).
template <class Select>
std::vector<char> pointsWhere(const std::vector<Vec3>& points, Select&& select)
{
  std::vector<char> flags(points.size(), 0);
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    flags[i] = select(points[i]) ? 1 : 0;
  }
  return flags;
}

/// The indices of the points where `select(point)` holds (a condition's set).
template <class Select>
std::vector<std::int32_t> indicesWhere(const std::vector<Vec3>& points, Select&& select)
{
  std::vector<std::int32_t> set;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    if (select(points[i]))
    {
      set.push_back(static_cast<std::int32_t>(i));
    }
  }
  return set;
}

inline std::vector<Vec3> randomVectors(std::size_t count, double amplitude, unsigned seed = 11)
{
  return jitter(std::vector<Vec3>(count, Vec3::Zero()), amplitude, seed);
}

/// The patch test's start: the flagged points of `positions` moved to a X + b of their rest
/// places X, the others left as they are.
inline void placeOnAffineMap(std::vector<Vec3>& positions, const std::vector<Vec3>& rest,
  const std::vector<char>& flagged, const Eigen::Matrix3d& a, const Vec3& b)
{
  for (std::size_t i = 0; i < positions.size(); ++i)
  {
    if (flagged[i])
    {
      positions[i] = a * rest[i] + b;
    }
  }
}

} // namespace softbody::test
