#include "softbody/lattice/lattice.h"

#include "softbody/common/errors.h"
#include "softbody/mesh/mesh_generators.h" // kuhnCubeTets

#include <cstdlib>
#include <limits>
#include <utility>

namespace softbody
{

Lattice buildLattice(const LatticeGrid& grid, const std::vector<char>& inside)
{
  if (inside.size() != grid.nodeCount())
  {
    throw InvalidInputError("The inside flags do not match the lattice grid.");
  }
  if (!(grid.spacing > 0.0) || !grid.origin.allFinite())
  {
    throw InvalidInputError("The lattice spacing must be positive and its origin finite.");
  }
  Lattice lattice;
  lattice.grid = grid;
  lattice.particleOfNode.assign(grid.nodeCount(), -1);
  for (int k = 0; k < grid.nodes[2]; ++k)
  {
    for (int j = 0; j < grid.nodes[1]; ++j)
    {
      for (int i = 0; i < grid.nodes[0]; ++i)
      {
        const std::size_t node = grid.nodeIndex(i, j, k);
        if (!inside[node])
        {
          continue;
        }
        if (lattice.points.size() >= std::size_t(std::numeric_limits<std::int32_t>::max()))
        {
          throw InvalidInputError("The lattice has more than 2^31 - 1 particles; use a larger spacing.");
        }
        lattice.particleOfNode[node] = static_cast<std::int32_t>(lattice.points.size());
        lattice.points.push_back(grid.position(i, j, k));
        lattice.nodeOfParticle.push_back({ i, j, k });
      }
    }
  }

  // The 13 "forward" offsets of the 26-neighborhood: each unordered neighbor pair is met once.
  std::vector<std::array<int, 3>> forward;
  for (int dk = -1; dk <= 1; ++dk)
  {
    for (int dj = -1; dj <= 1; ++dj)
    {
      for (int di = -1; di <= 1; ++di)
      {
        const bool positive = dk > 0 || (dk == 0 && (dj > 0 || (dj == 0 && di > 0)));
        if (positive)
        {
          forward.push_back({ di, dj, dk });
        }
      }
    }
  }
  for (std::size_t p = 0; p < lattice.points.size(); ++p)
  {
    const auto& n = lattice.nodeOfParticle[p];
    for (const auto& d : forward)
    {
      const int i = n[0] + d[0], j = n[1] + d[1], k = n[2] + d[2];
      if (i < 0 || j < 0 || k < 0 || i >= grid.nodes[0] || j >= grid.nodes[1] || k >= grid.nodes[2])
      {
        continue;
      }
      const std::int32_t q = lattice.particleOfNode[grid.nodeIndex(i, j, k)];
      if (q < 0)
      {
        continue;
      }
      lattice.links.push_back({ static_cast<std::int32_t>(p), q });
      const int nonzero = std::abs(d[0]) + std::abs(d[1]) + std::abs(d[2]);
      lattice.linkKinds.push_back(static_cast<LatticeLinkKind>(nonzero - 1));
    }
  }
  return lattice;
}

std::vector<Tet> latticeTets(const Lattice& lattice)
{
  const LatticeGrid& grid = lattice.grid;
  const auto kuhn = kuhnCubeTets();
  std::vector<Tet> tets;
  for (int k = 0; k + 1 < grid.nodes[2]; ++k)
  {
    for (int j = 0; j + 1 < grid.nodes[1]; ++j)
    {
      for (int i = 0; i + 1 < grid.nodes[0]; ++i)
      {
        auto particle = [&](const std::array<int, 3>& c) {
          return lattice.particleOfNode[grid.nodeIndex(i + c[0], j + c[1], k + c[2])];
        };
        bool full = true;
        for (int c = 0; c < 8 && full; ++c)
        {
          full = particle({ c & 1, (c >> 1) & 1, (c >> 2) & 1 }) >= 0;
        }
        if (!full)
        {
          continue;
        }
        for (const auto& corners : kuhn)
        {
          Tet tet;
          for (std::size_t c = 0; c < 4; ++c)
          {
            tet[c] = particle(corners[c]);
          }
          const auto& p = lattice.points;
          if (signedTetVolume(p[std::size_t(tet[0])], p[std::size_t(tet[1])], p[std::size_t(tet[2])], p[std::size_t(tet[3])]) < 0.0)
          {
            std::swap(tet[2], tet[3]);
          }
          tets.push_back(tet);
        }
      }
    }
  }
  return tets;
}

} // namespace softbody
