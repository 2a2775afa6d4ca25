#include "softbody/lattice/skinning.h"

#include "softbody/common/errors.h"
#include "softbody/common/parallel.h"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <deque>

namespace softbody
{
namespace
{
/// Trilinear weights of the 8 corners (x fastest) at local coordinates t (any real values).
std::array<double, 8> trilinear(const Vec3& t)
{
  std::array<double, 8> w{};
  for (int corner = 0; corner < 8; ++corner)
  {
    const double wx = (corner & 1) ? t.x() : 1.0 - t.x();
    const double wy = (corner & 2) ? t.y() : 1.0 - t.y();
    const double wz = (corner & 4) ? t.z() : 1.0 - t.z();
    w[static_cast<std::size_t>(corner)] = wx * wy * wz;
  }
  return w;
}
} // namespace

Skin bindToLattice(const Lattice& lattice, const std::vector<Vec3>& vertices)
{
  const LatticeGrid& grid = lattice.grid;
  const std::array<int, 3> cells = { grid.nodes[0] - 1, grid.nodes[1] - 1, grid.nodes[2] - 1 };
  if (cells[0] < 1 || cells[1] < 1 || cells[2] < 1)
  {
    throw InvalidInputError("The lattice is too thin to skin a surface onto (no full cell): use a smaller spacing.");
  }
  auto cellIndex = [&](int i, int j, int k) {
    return (std::size_t(k) * std::size_t(cells[1]) + std::size_t(j)) * std::size_t(cells[0]) + std::size_t(i);
  };
  auto corner = [&](int i, int j, int k, int c) {
    return lattice.particleOfNode[grid.nodeIndex(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1))];
  };

  // Nearest full cell of every cell: a multi-source breadth-first sweep over the 26-connected
  // cell grid, seeded with the full cells.
  const std::size_t cellCount = std::size_t(cells[0]) * std::size_t(cells[1]) * std::size_t(cells[2]);
  std::vector<std::int64_t> nearest(cellCount, -1);
  std::deque<std::array<int, 3>> queue;
  for (int k = 0; k < cells[2]; ++k)
  {
    for (int j = 0; j < cells[1]; ++j)
    {
      for (int i = 0; i < cells[0]; ++i)
      {
        bool full = true;
        for (int c = 0; c < 8 && full; ++c)
        {
          full = corner(i, j, k, c) >= 0;
        }
        if (full)
        {
          nearest[cellIndex(i, j, k)] = static_cast<std::int64_t>(cellIndex(i, j, k));
          queue.push_back({ i, j, k });
        }
      }
    }
  }
  if (queue.empty())
  {
    throw InvalidInputError("The lattice has no full cell (8 particles around a voxel) to skin a surface onto: use a smaller spacing.");
  }
  while (!queue.empty())
  {
    const auto c = queue.front();
    queue.pop_front();
    const std::int64_t source = nearest[cellIndex(c[0], c[1], c[2])];
    for (int dk = -1; dk <= 1; ++dk)
    {
      for (int dj = -1; dj <= 1; ++dj)
      {
        for (int di = -1; di <= 1; ++di)
        {
          const int i = c[0] + di, j = c[1] + dj, k = c[2] + dk;
          if (i < 0 || j < 0 || k < 0 || i >= cells[0] || j >= cells[1] || k >= cells[2])
          {
            continue;
          }
          std::int64_t& target = nearest[cellIndex(i, j, k)];
          if (target < 0)
          {
            target = source;
            queue.push_back({ i, j, k });
          }
        }
      }
    }
  }

  Skin skin;
  skin.offsets.reserve(vertices.size() + 1);
  skin.offsets.push_back(0);
  for (const Vec3& v : vertices)
  {
    if (!v.allFinite())
    {
      throw InvalidInputError("The surface to skin has NaN or infinite coordinates.");
    }
    const Vec3 local = (v - grid.origin) / grid.spacing;
    std::array<int, 3> c{};
    for (int a = 0; a < 3; ++a)
    {
      c[static_cast<std::size_t>(a)] = std::clamp(static_cast<int>(std::floor(local[a])), 0, cells[static_cast<std::size_t>(a)] - 1);
    }
    const std::size_t own = cellIndex(c[0], c[1], c[2]);
    const std::size_t chosen = static_cast<std::size_t>(nearest[own]);
    if (chosen != own || (local - Vec3(c[0], c[1], c[2])).minCoeff() < 0.0 ||
      (local - Vec3(c[0], c[1], c[2])).maxCoeff() > 1.0)
    {
      ++skin.outsideCount;
    }
    const int ci = static_cast<int>(chosen % std::size_t(cells[0]));
    const int cj = static_cast<int>((chosen / std::size_t(cells[0])) % std::size_t(cells[1]));
    const int ck = static_cast<int>(chosen / (std::size_t(cells[0]) * std::size_t(cells[1])));
    const std::array<double, 8> w = trilinear(local - Vec3(ci, cj, ck));
    for (int k = 0; k < 8; ++k)
    {
      skin.particles.push_back(corner(ci, cj, ck, k));
      skin.weights.push_back(w[static_cast<std::size_t>(k)]);
    }
    skin.offsets.push_back(static_cast<std::int32_t>(skin.particles.size()));
  }
  return skin;
}

Skin bindToTets(const std::vector<Vec3>& points, const std::vector<Tet>& tets,
  const std::vector<Vec3>& vertices, const std::vector<std::int32_t>& tetOfVertex)
{
  if (tetOfVertex.size() != vertices.size())
  {
    throw InvalidInputError("Every surface vertex needs a tet to bind to.");
  }
  Skin skin;
  skin.offsets.push_back(0);
  for (std::size_t v = 0; v < vertices.size(); ++v)
  {
    const std::int32_t t = tetOfVertex[v];
    if (t < 0 || std::size_t(t) >= tets.size() || !vertices[v].allFinite())
    {
      throw InvalidInputError("A surface vertex has no tet to bind to, or non-finite coordinates.");
    }
    const Tet& tet = tets[std::size_t(t)];
    const Vec3& p0 = points[std::size_t(tet[0])];
    Eigen::Matrix3d edges;
    edges << points[std::size_t(tet[1])] - p0, points[std::size_t(tet[2])] - p0, points[std::size_t(tet[3])] - p0;
    // Barycentric coordinates: v = p0 + E b, weights (1 - sum b, b).
    const Vec3 b = edges.partialPivLu().solve(vertices[v] - p0);
    const double w0 = 1.0 - b.sum();
    if (std::min(w0, b.minCoeff()) < -1e-9)
    {
      ++skin.outsideCount;
    }
    const double weights[4] = { w0, b.x(), b.y(), b.z() };
    for (int k = 0; k < 4; ++k)
    {
      skin.particles.push_back(tet[static_cast<std::size_t>(k)]);
      skin.weights.push_back(weights[k]);
    }
    skin.offsets.push_back(static_cast<std::int32_t>(skin.particles.size()));
  }
  return skin;
}

void applySkin(const Skin& skin, const std::vector<Vec3>& particlePositions, std::vector<Vec3>& vertices)
{
  vertices.resize(skin.vertexCount());
  parallelFor(skin.vertexCount(), 1024, [&](std::size_t v) {
    Vec3 x = Vec3::Zero();
    for (std::int32_t e = skin.offsets[v]; e < skin.offsets[v + 1]; ++e)
    {
      x += skin.weights[std::size_t(e)] * particlePositions[std::size_t(skin.particles[std::size_t(e)])];
    }
    vertices[v] = x;
  });
}

} // namespace softbody
