// The matrix each coordinate's motion shares in a backward-Euler step of h:
//
//   A(h) = M / h^2 + sum over elements of their isotropic stiffness weights
//
// (springs k + c / h; the network's volume term by its gradients' Laplacian; continuum tets
// (2 mu + lambda) V0 (1 + beta / h) g_a . g_b), over the points that move (inverse mass > 0).
// Entries that couple a free point to a fixed one stay on the free point's diagonal: the fixed
// one does not move, so this is the matrix of the free unknowns.
//
// It is Projective Dynamics' global matrix (Bouaziz et al. 2014), and h^2 A is an isotropic
// stand-in for the Hessian M + h^2 K of the step: the same for x, y and z, independent of the
// deformation, and seeing the whole mesh's coupling (which block Jacobi does not), so one
// factor of it preconditions Newton's conjugate gradients for many steps
// (coordinate_preconditioner.h).
#pragma once

#include "softbody/massspring/model_potential_factory.h"
#include "softbody/material/mass.h"
#include "softbody/mesh/topology.h"

#include <Eigen/SparseCore>

#include <cstdint>
#include <vector>

namespace softbody
{

class CoordinateMatrix
{
public:
  CoordinateMatrix(const Topology& topology, const BodyElements& elements,
    const PointMasses& masses, const std::vector<Vec3>& restPositions);

  /// A(h) over the free points, in their order. With `inertia` false, M / h^2 is left out but
  /// the damping terms still use h (the static solve's matrix has neither: pass h = infinity).
  Eigen::SparseMatrix<double> assemble(double h, bool inertia = true) const;

  std::size_t rowCount() const { return FreeVertex.size(); }
  /// Row of A -> vertex, and vertex -> row (-1 for a fixed point).
  const std::vector<std::int32_t>& freeVertices() const { return FreeVertex; }
  std::int32_t rowOf(std::size_t vertex) const { return FreeIndex[vertex]; }

private:
  const Topology& Topo;
  const ElementConstants& Network;
  const TetElasticConstants* Tets; ///< the continuum models' (null for the network)
  const std::vector<double>& InverseMass;
  std::vector<double> TetWeight;        ///< sum_c |dV/dp_c|^2 at rest: the volume term's Laplacian weight
  std::vector<std::int32_t> FreeIndex;  ///< vertex -> row of A, -1 for fixed points
  std::vector<std::int32_t> FreeVertex; ///< row of A -> vertex
};

} // namespace softbody
