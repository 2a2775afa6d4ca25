#include "softbody/massspring/incremental_potential.h"

#include "softbody/common/parallel.h"

#include <algorithm>
#include <cmath>

namespace softbody
{
namespace
{

constexpr std::size_t kElementGrain = 2048;
constexpr std::size_t kVertexGrain = 512;

/// Index into Topology::tetEdges' row of the edge between corners c and j (c != j), in the
/// order of topology.cpp's kTetEdgeCorners {01, 02, 03, 12, 13, 23}.
constexpr int kLocalEdge[4][4] = { { -1, 0, 1, 2 }, { 0, -1, 3, 4 }, { 1, 3, -1, 5 },
  { 2, 4, 5, -1 } };

} // namespace

IncrementalPotential::IncrementalPotential(const Topology& topology,
  const ElementConstants& constants, const PointMasses& masses, const Vec3& gravity)
  : Topo(topology)
  , Constants(constants)
  , InverseMass(masses.inverseMass)
  , Gravity(gravity)
{
  Active.resize(topology.vertexCount);
  for (std::size_t i = 0; i < topology.vertexCount; ++i)
  {
    Active[i] = InverseMass[i] > 0.0 ? 1 : 0;
    ActiveMass += Active[i] ? 1.0 / InverseMass[i] : 0.0;
  }
}

void IncrementalPotential::beginStep(
  const std::vector<Vec3>& x0, const std::vector<Vec3>& v0, double h)
{
  H = h;
  X0 = x0;
  const double momentum = parallelSum(x0.size(), [&](std::size_t i) {
    return Active[i] ? v0[i].squaredNorm() / InverseMass[i] : 0.0;
  });
  SpeedScale = ActiveMass > 0.0 ? std::sqrt(momentum / ActiveMass) : 0.0;
  Target.resize(x0.size());
  parallelFor(x0.size(), 4096, [&](std::size_t i) {
    Target[i] = Active[i] ? Vec3(x0[i] + h * v0[i]) : x0[i];
  });
  DampingAxis.resize(Topo.edges.size());
  parallelFor(Topo.edges.size(), kElementGrain, [&](std::size_t e) {
    const Vec3 d = x0[Topo.edges[e].a] - x0[Topo.edges[e].b];
    const double length = d.norm();
    DampingAxis[e] = length > 0.0 ? Vec3(d / length) : Vec3::Zero();
  });
  DampingGradient.resize(Constants.hasVolumeTerm ? Topo.tets.size() : 0);
  parallelFor(DampingGradient.size(), kElementGrain, [&](std::size_t t) {
    const Tet& tet = Topo.tets[t];
    DampingGradient[t] = tetVolumeGradients(x0[tet[0]], x0[tet[1]], x0[tet[2]], x0[tet[3]]);
  });
}

void IncrementalPotential::predict(std::vector<Vec3>& x, bool withGravity) const
{
  const Vec3 drift = withGravity ? Vec3(H * H * Gravity) : Vec3::Zero();
  x.resize(Target.size());
  parallelFor(Target.size(), 4096, [&](std::size_t i) { x[i] = Active[i] ? Vec3(Target[i] + drift) : X0[i]; });
}

void IncrementalPotential::elementPass(const std::vector<Vec3>& x)
{
  const ElementConstants& c = Constants;
  const std::size_t edgeCount = Topo.edges.size();
  SpringGradient.resize(edgeCount);
  ElementEnergy.resize(edgeCount + (c.hasVolumeTerm ? Topo.tets.size() : 0));
  parallelFor(edgeCount, kElementGrain, [&](std::size_t e) {
    const Edge& edge = Topo.edges[e];
    const Vec3 d = x[edge.a] - x[edge.b];
    const double length = d.norm();
    const double k = c.springStiffness[e];
    const double stretch = length - c.restLength[e];
    const Vec3& n0 = DampingAxis[e];
    const double dampingRate = n0.dot((x[edge.a] - X0[edge.a]) - (x[edge.b] - X0[edge.b])) / H;
    const double kd = c.springDamping[e];
    ElementEnergy[e] = 0.5 * k * stretch * stretch + 0.5 * kd * H * dampingRate * dampingRate;
    Vec3 gradient = kd * dampingRate * n0;
    if (length > 1e-12 * c.restLength[e])
    {
      gradient += (k * stretch / length) * d;
    }
    SpringGradient[e] = gradient;
  });
  if (!c.hasVolumeTerm)
  {
    TetGradient.clear();
    return;
  }
  TetGradient.resize(Topo.tets.size());
  TetScale.resize(Topo.tets.size());
  TetDampingScale.resize(Topo.tets.size());
  parallelFor(Topo.tets.size(), kElementGrain, [&](std::size_t t) {
    const Tet& tet = Topo.tets[t];
    TetGradient[t] = tetVolumeGradients(x[tet[0]], x[tet[1]], x[tet[2]], x[tet[3]]);
    const double dv =
      signedTetVolume(x[tet[0]], x[tet[1]], x[tet[2]], x[tet[3]]) - c.restVolume[t];
    double rate = 0.0; // dV/dt linearized at the step's start, (g0 . dx) / h
    for (int k = 0; k < 4; ++k)
    {
      rate += DampingGradient[t][k].dot(x[tet[k]] - X0[tet[k]]);
    }
    rate /= H;
    TetScale[t] = c.volumeStiffness[t] * dv;
    TetDampingScale[t] = c.volumeDamping[t] * rate;
    ElementEnergy[edgeCount + t] =
      0.5 * c.volumeStiffness[t] * dv * dv + 0.5 * c.volumeDamping[t] * H * rate * rate;
  });
}

double IncrementalPotential::evaluate(const std::vector<Vec3>& x, std::vector<Vec3>& gradient)
{
  elementPass(x);
  const double h2 = H * H;
  gradient.resize(x.size());
  parallelFor(x.size(), kVertexGrain, [&](std::size_t i) {
    if (!Active[i])
    {
      gradient[i].setZero();
      return;
    }
    const double m = 1.0 / InverseMass[i];
    Vec3 sum = m * ((x[i] - Target[i]) / h2 - Gravity);
    const Csr& edges = Topo.vertexEdges;
    for (std::int32_t k = edges.offsets[i]; k < edges.offsets[i + 1]; ++k)
    {
      const std::int32_t e = edges.items[k];
      sum += Topo.edges[e].a == static_cast<std::int32_t>(i) ? SpringGradient[e]
                                                             : Vec3(-SpringGradient[e]);
    }
    if (!TetGradient.empty())
    {
      const Csr& corners = Topo.vertexTetCorners;
      for (std::int32_t k = corners.offsets[i]; k < corners.offsets[i + 1]; ++k)
      {
        const std::int32_t t = corners.items[k] / 4, corner = corners.items[k] % 4;
        sum += TetScale[t] * TetGradient[t][corner] +
          TetDampingScale[t] * DampingGradient[t][corner];
      }
    }
    gradient[i] = sum;
  });
  const double inertia = parallelSum(x.size(), [&](std::size_t i) {
    if (!Active[i])
    {
      return 0.0;
    }
    const double m = 1.0 / InverseMass[i];
    // Gravity's work from x0 rather than from the origin: the same minimizer, and Phi stays
    // small enough that its rounding does not hide the last iterations' progress.
    return 0.5 * m * (x[i] - Target[i]).squaredNorm() / h2 - m * Gravity.dot(x[i] - X0[i]);
  });
  return inertia + parallelSum(ElementEnergy.size(), [&](std::size_t e) { return ElementEnergy[e]; });
}

void IncrementalPotential::springHessianPass(const std::vector<Vec3>& x)
{
  const ElementConstants& c = Constants;
  SpringHessian.resize(Topo.edges.size());
  parallelFor(Topo.edges.size(), kElementGrain, [&](std::size_t e) {
    const Edge& edge = Topo.edges[e];
    const Vec3 d = x[edge.a] - x[edge.b];
    const double length = d.norm();
    const double k = c.springStiffness[e];
    const Vec3& n0 = DampingAxis[e];
    Mat3 hessian = (c.springDamping[e] / H) * n0 * n0.transpose();
    if (length > 1e-12 * c.restLength[e])
    {
      const Vec3 n = d / length;
      const Mat3 axial = n * n.transpose();
      // Transverse stiffness k (1 - l0/l) is negative for a compressed spring: clamp to 0.
      const double transverse = std::max(0.0, 1.0 - c.restLength[e] / length);
      hessian += k * (axial + transverse * (Mat3::Identity() - axial));
    }
    else
    {
      hessian += k * Mat3::Identity(); // no direction: isotropic, still positive
    }
    SpringHessian[e] = hessian;
  });
}

void IncrementalPotential::assembleHessian(const std::vector<Vec3>& x, BlockSparseMatrix& hessian)
{
  springHessianPass(x);
  if (!TetGradient.empty() && CornerSlots.empty())
  {
    findCornerSlots(hessian);
  }
  const double h2 = H * H;
  parallelFor(Topo.vertexCount, kVertexGrain, [&](std::size_t i) {
    const std::int32_t row = static_cast<std::int32_t>(i);
    Mat3& diagonal = hessian.block(hessian.diagonalSlot(i));
    const Csr& edges = Topo.vertexEdges;
    if (!Active[i])
    {
      diagonal.setIdentity();
      for (std::int32_t k = edges.offsets[i]; k < edges.offsets[i + 1]; ++k)
      {
        hessian.block(hessian.edgeSlot(edges.items[k], row, Topo)).setZero();
      }
      return;
    }
    diagonal = Mat3::Identity() / (h2 * InverseMass[i]);
    for (std::int32_t k = edges.offsets[i]; k < edges.offsets[i + 1]; ++k)
    {
      const std::int32_t e = edges.items[k];
      diagonal += SpringHessian[e];
      hessian.block(hessian.edgeSlot(e, row, Topo)) = -SpringHessian[e];
    }
    if (TetGradient.empty())
    {
      return;
    }
    const Csr& corners = Topo.vertexTetCorners;
    for (std::int32_t k = corners.offsets[i]; k < corners.offsets[i + 1]; ++k)
    {
      const std::int32_t tetCorner = corners.items[k];
      const std::int32_t t = tetCorner / 4, c = tetCorner % 4;
      // Volume damping's exact Hessian is (Kd / h) g0 g0^T with the step's initial gradients;
      // g differs from g0 by one step's deformation, so (K + Kd / h) g g^T halves the outer
      // products at the cost of an O(h) error in a term Newton only needs approximately (the
      // gradient, and so the answer, keeps g0).
      const double weight = Constants.volumeStiffness[t] + Constants.volumeDamping[t] / H;
      const std::array<Vec3, 4>& g = TetGradient[t];
      const Vec3 wg = weight * g[c];
      diagonal.noalias() += wg * g[c].transpose();
      const std::array<std::int32_t, 3>& slots = CornerSlots[static_cast<std::size_t>(tetCorner)];
      for (int j = 0, k3 = 0; j < 4; ++j)
      {
        if (j != c)
        {
          hessian.block(slots[k3++]).noalias() += wg * g[j].transpose();
        }
      }
    }
  });
}

void IncrementalPotential::findCornerSlots(const BlockSparseMatrix& hessian)
{
  // Each tet corner's three off-diagonal blocks, found once: the assembly then writes without
  // looking up edges.
  CornerSlots.resize(4 * Topo.tets.size());
  parallelFor(Topo.tets.size(), kElementGrain, [&](std::size_t t) {
    for (int c = 0; c < 4; ++c)
    {
      for (int j = 0, k = 0; j < 4; ++j)
      {
        if (j != c)
        {
          const std::int32_t e = Topo.tetEdges.items[6 * t + kLocalEdge[c][j]];
          CornerSlots[4 * t + c][k++] = hessian.edgeSlot(e, Topo.tets[t][c], Topo);
        }
      }
    }
  });
}

double IncrementalPotential::referenceAcceleration(double gravityNorm) const
{
  return std::max({ gravityNorm, SpeedScale / H, 1e-12 });
}

double IncrementalPotential::residualAcceleration(const std::vector<Vec3>& gradient) const
{
  if (!(ActiveMass > 0.0))
  {
    return 0.0;
  }
  const double sum = parallelSum(gradient.size(), [&](std::size_t i) {
    return Active[i] ? gradient[i].squaredNorm() * InverseMass[i] : 0.0;
  });
  return std::sqrt(sum / ActiveMass);
}

} // namespace softbody
