#include "softbody/mesh/mesh_generators.h"

#include "softbody/common/errors.h"

#include <algorithm>
#include <array>

namespace softbody
{

std::array<std::array<std::array<int, 3>, 4>, 6> kuhnCubeTets()
{
  std::array<std::array<std::array<int, 3>, 4>, 6> tets{};
  std::array<int, 3> axes{ 0, 1, 2 };
  std::size_t t = 0;
  do
  {
    auto& corners = tets[t++];
    for (int c = 1; c < 4; ++c)
    {
      corners[std::size_t(c)] = corners[std::size_t(c - 1)];
      corners[std::size_t(c)][std::size_t(axes[std::size_t(c - 1)])] = 1;
    }
  } while (std::next_permutation(axes.begin(), axes.end()));
  return tets;
}

TetMesh makeTetBox(int nx, int ny, int nz, double cellSize, const Vec3& origin)
{
  if (nx < 1 || ny < 1 || nz < 1 || !(cellSize > 0.0))
  {
    throw InvalidInputError("makeTetBox needs at least one cell per axis and a positive size.");
  }
  TetMesh mesh;
  auto index = [&](int i, int j, int k) { return static_cast<std::int32_t>(i + (nx + 1) * (j + (ny + 1) * k)); };
  for (int k = 0; k <= nz; ++k)
  {
    for (int j = 0; j <= ny; ++j)
    {
      for (int i = 0; i <= nx; ++i)
      {
        mesh.points.push_back(origin + cellSize * Vec3(i, j, k));
      }
    }
  }
  const auto kuhnTets = kuhnCubeTets();

  for (int k = 0; k < nz; ++k)
  {
    for (int j = 0; j < ny; ++j)
    {
      for (int i = 0; i < nx; ++i)
      {
        for (const auto& corners : kuhnTets)
        {
          Tet tet;
          for (int c = 0; c < 4; ++c)
          {
            tet[c] = index(i + corners[c][0], j + corners[c][1], k + corners[c][2]);
          }
          const auto& p = mesh.points;
          if (signedTetVolume(p[tet[0]], p[tet[1]], p[tet[2]], p[tet[3]]) < 0.0)
          {
            std::swap(tet[2], tet[3]);
          }
          mesh.tets.push_back(tet);
        }
      }
    }
  }
  return mesh;
}

} // namespace softbody
