// A particle lattice: the nodes of a regular grid that lie inside a body, linked to their lattice
// neighbors within one voxel diagonal (the 26-neighborhood), as the PBD thesis's voxelized
// bodies. Built in time linear in the number of grid nodes (a dense node -> particle map), never
// by an all-pairs search.
#pragma once

#include "softbody/common/geometry.h"

#include <array>
#include <cstdint>
#include <vector>

namespace softbody
{

struct LatticeGrid
{
  Vec3 origin{ 0.0, 0.0, 0.0 }; ///< position of node (0, 0, 0) [m]
  double spacing = 1.0;         ///< node distance h [m]
  std::array<int, 3> nodes{ 0, 0, 0 }; ///< node counts along x, y, z

  std::size_t nodeCount() const { return std::size_t(nodes[0]) * std::size_t(nodes[1]) * std::size_t(nodes[2]); }
  /// Node index with x fastest.
  std::size_t nodeIndex(int i, int j, int k) const
  {
    return (std::size_t(k) * std::size_t(nodes[1]) + std::size_t(j)) * std::size_t(nodes[0]) + std::size_t(i);
  }
  Vec3 position(int i, int j, int k) const { return origin + spacing * Vec3(i, j, k); }
};

enum class LatticeLinkKind : unsigned char
{
  Axis = 0,         ///< length h
  FaceDiagonal = 1, ///< length h sqrt(2)
  BodyDiagonal = 2  ///< length h sqrt(3)
};

struct Lattice
{
  LatticeGrid grid;
  std::vector<Vec3> points;                        ///< one particle per inside node
  std::vector<std::array<int, 3>> nodeOfParticle;  ///< its (i, j, k)
  std::vector<std::int32_t> particleOfNode;        ///< per grid node: particle index or -1
  std::vector<std::array<std::int32_t, 2>> links;  ///< each neighbor pair once
  std::vector<LatticeLinkKind> linkKinds;
};

/// `inside[grid.nodeIndex(i, j, k)]` nonzero marks the nodes that become particles.
Lattice buildLattice(const LatticeGrid& grid, const std::vector<char>& inside);

/// The lattice as a tet mesh: every full cell (all 8 corners are particles) split into its 6
/// Kuhn tets, positively oriented, conforming between cells. Particles of no full cell are in no
/// tet.
std::vector<Tet> latticeTets(const Lattice& lattice);

} // namespace softbody
