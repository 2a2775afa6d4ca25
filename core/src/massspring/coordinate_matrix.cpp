#include "softbody/massspring/coordinate_matrix.h"

#include "softbody/common/geometry.h"

#include <array>
#include <cmath>

namespace softbody
{

CoordinateMatrix::CoordinateMatrix(const Topology& topology, const BodyElements& elements,
  const PointMasses& masses, const std::vector<Vec3>& restPositions)
  : Topo(topology)
  , Network(*elements.network)
  , Tets(isContinuum(elements.model) ? elements.tets : nullptr)
  , InverseMass(masses.inverseMass)
{
  FreeIndex.assign(topology.vertexCount, -1);
  for (std::size_t i = 0; i < topology.vertexCount; ++i)
  {
    if (InverseMass[i] > 0.0)
    {
      FreeIndex[i] = static_cast<std::int32_t>(FreeVertex.size());
      FreeVertex.push_back(static_cast<std::int32_t>(i));
    }
  }
  if (Network.hasVolumeTerm)
  {
    TetWeight.resize(topology.tets.size());
    for (std::size_t t = 0; t < topology.tets.size(); ++t)
    {
      const Tet& tet = topology.tets[t];
      const auto g = tetVolumeGradients(restPositions[tet[0]], restPositions[tet[1]],
        restPositions[tet[2]], restPositions[tet[3]]);
      TetWeight[t] = g[0].squaredNorm() + g[1].squaredNorm() + g[2].squaredNorm() +
        g[3].squaredNorm();
    }
  }
}

Eigen::SparseMatrix<double> CoordinateMatrix::assemble(double h, bool inertia) const
{
  using Triplet = Eigen::Triplet<double>;
  std::vector<Triplet> entries;
  entries.reserve(FreeVertex.size() + 4 * Topo.edges.size() + 16 * Topo.tets.size());
  // Damping's share of a step: c / h (none for h = infinity).
  const auto overStep = [&](double damping) { return std::isfinite(h) ? damping / h : 0.0; };
  for (std::size_t r = 0; r < FreeVertex.size(); ++r)
  {
    const int row = static_cast<int>(r);
    entries.emplace_back(row, row, inertia ? 1.0 / (h * h * InverseMass[FreeVertex[r]]) : 0.0);
  }
  const auto addPair = [&](std::int32_t i, std::int32_t j, double weight) {
    const int fi = FreeIndex[i], fj = FreeIndex[j];
    if (fi >= 0 && fj >= 0)
    {
      entries.emplace_back(fi, fj, weight);
    }
  };
  for (std::size_t e = 0; e < Topo.edges.size(); ++e)
  {
    const double w = Network.springStiffness[e] + overStep(Network.springDamping[e]);
    const Edge& edge = Topo.edges[e];
    addPair(edge.a, edge.a, w);
    addPair(edge.b, edge.b, w);
    addPair(edge.a, edge.b, -w);
    addPair(edge.b, edge.a, -w);
  }
  for (std::size_t t = 0; t < TetWeight.size(); ++t)
  {
    const double w = (Network.volumeStiffness[t] + overStep(Network.volumeDamping[t])) * TetWeight[t];
    const Tet& tet = Topo.tets[t];
    for (int a = 0; a < 4; ++a)
    {
      for (int b = 0; b < 4; ++b)
      {
        addPair(tet[a], tet[b], w * ((a == b ? 1.0 : 0.0) - 0.25));
      }
    }
  }
  for (std::size_t t = 0; Tets && t < Topo.tets.size(); ++t)
  {
    const LameParameters& p = Tets->linear[t];
    const double viscosity = Tets->damped ? overStep(Tets->dampingTime[t]) : 0.0;
    const double w = (2.0 * p.mu + p.lambda) * Tets->restVolume[t] * (1.0 + viscosity);
    const std::array<Vec3, 4>& g = Tets->shapeGradients[t];
    const Tet& tet = Topo.tets[t];
    for (int a = 0; a < 4; ++a)
    {
      for (int b = 0; b < 4; ++b)
      {
        addPair(tet[a], tet[b], w * g[static_cast<std::size_t>(a)].dot(g[static_cast<std::size_t>(b)]));
      }
    }
  }
  const auto rows = static_cast<Eigen::Index>(FreeVertex.size());
  Eigen::SparseMatrix<double> matrix(rows, rows);
  matrix.setFromTriplets(entries.begin(), entries.end());
  matrix.makeCompressed();
  return matrix;
}

} // namespace softbody
