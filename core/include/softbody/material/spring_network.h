// The spring-and-volume network of Teschner et al. 2004 ("A versatile and robust model for
// geometrically complex deformable solids"; constants from material.h) written as two element
// families of element_model.h: springs on the mesh's edges and volume terms on its tets.
//
// Per spring e between points a and b, with d = x_a - x_b, l = |d|, k = k_D / l0^2 [N/m]:
//   E_e  = k / 2 (l - l0)^2 + kd h / 2 r^2,   r = n0 . (dx_a - dx_b) / h   (dx = x - x0)
//   dE/dx_a = k (l - l0) / l d + kd r n0 = -dE/dx_b
//   H_aa = H_bb = -H_ab = k [n n^T + max(0, 1 - l0/l) (I - n n^T)] + (kd / h) n0 n0^T
// with n = d / l and n0 the spring's axis at x0 (its damping direction, frozen for the step).
// Per tet t with signed volume V, gradients g_c = dV/dx_c [m^2], K = k_V / V0^2 [N/m^5]:
//   E_t  = K / 2 (V - V0)^2 + Kd h / 2 r^2,   r = sum_c g0_c . dx_c / h
//   dE/dx_c = K (V - V0) g_c + Kd r g0_c
//   H_cj = (K + Kd / h) g_c g_j^T   (Gauss-Newton; g0 replaced by g in the damping block)
// The Hessians' projection and the reasons for its two approximations are in
// incremental_potential.h's header comment. Every expression is written in the order the
// incremental potential has always evaluated it, so results are the same to the last bit.
#pragma once

#include "softbody/material/element_model.h"
#include "softbody/material/material.h"
#include "softbody/material/tet_corners.h"
#include "softbody/mesh/topology.h"

#include <algorithm>
#include <tuple>

namespace softbody
{

/// Springs on the mesh's edges; corner 0 is the edge's point a, corner 1 its point b.
class SpringFamily
{
public:
  static constexpr int kCorners = 2;
  using StepData = Vec3; ///< n0: the spring's unit axis at x0 (zero for a collapsed spring)
  struct AtX
  {
    Vec3 gradient; ///< dE/dx_a [N]; corner b gets its negative
  };
  using HessianData = Mat3; ///< H_aa [N/m]

  SpringFamily(const Topology& topology, const ElementConstants& constants)
    : Topo(&topology)
    , Constants(&constants)
  {
  }

  std::size_t size() const { return Topo->edges.size(); }
  std::array<std::int32_t, 2> corners(std::size_t e) const
  {
    return { Topo->edges[e].a, Topo->edges[e].b };
  }
  std::int32_t edgeBetween(std::size_t e, int, int) const { return static_cast<std::int32_t>(e); }

  /// visit(edge, corner) for each spring at `vertex`, in Topology::vertexEdges' order.
  template <class Visit>
  void forEachCorner(std::int32_t vertex, Visit&& visit) const
  {
    const Csr& edges = Topo->vertexEdges;
    for (std::int32_t k = edges.offsets[static_cast<std::size_t>(vertex)];
         k < edges.offsets[static_cast<std::size_t>(vertex) + 1]; ++k)
    {
      const std::int32_t e = edges.items[static_cast<std::size_t>(k)];
      visit(static_cast<std::size_t>(e), Topo->edges[static_cast<std::size_t>(e)].a == vertex ? 0 : 1);
    }
  }

  StepData stepData(std::size_t e, const std::vector<Vec3>& x0) const
  {
    const Vec3 d = x0[Topo->edges[e].a] - x0[Topo->edges[e].b];
    const double length = d.norm();
    return length > 0.0 ? Vec3(d / length) : Vec3::Zero();
  }

  double evaluate(std::size_t e, const std::vector<Vec3>& x, const StepStart& start,
    const StepData& n0, AtX& out) const
  {
    const Edge& edge = Topo->edges[e];
    const ElementConstants& c = *Constants;
    const Vec3 d = x[edge.a] - x[edge.b];
    const double length = d.norm();
    const double k = c.springStiffness[e];
    const double stretch = length - c.restLength[e];
    const double dampingRate =
      n0.dot((x[edge.a] - start.x0[edge.a]) - (x[edge.b] - start.x0[edge.b])) / start.h;
    const double kd = c.springDamping[e];
    Vec3 gradient = kd * dampingRate * n0;
    if (length > 1e-12 * c.restLength[e])
    {
      gradient += (k * stretch / length) * d;
    }
    out.gradient = gradient;
    return 0.5 * k * stretch * stretch + 0.5 * kd * start.h * dampingRate * dampingRate;
  }

  Vec3 cornerGradient(const StepData&, const AtX& at, int corner) const
  {
    return corner == 0 ? at.gradient : Vec3(-at.gradient);
  }

  HessianData hessianData(std::size_t e, const std::vector<Vec3>& x, const StepStart& start,
    const StepData& n0, const AtX&) const
  {
    const Edge& edge = Topo->edges[e];
    const ElementConstants& c = *Constants;
    const Vec3 d = x[edge.a] - x[edge.b];
    const double length = d.norm();
    const double k = c.springStiffness[e];
    Mat3 hessian = (c.springDamping[e] / start.h) * n0 * n0.transpose();
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
    return hessian;
  }

  Mat3 hessianBlock(const StepData&, const AtX&, const HessianData& h, int a, int b) const
  {
    return a == b ? h : Mat3(-h);
  }

  /// Row norm bound of the axial stiffness at rest: |H_aa| + |H_ab| = 2k.
  double stiffnessBound(std::size_t e, int, const std::vector<Vec3>&) const
  {
    return 2.0 * Constants->springStiffness[e];
  }

private:
  const Topology* Topo;
  const ElementConstants* Constants;
};

/// Volume terms on the tets (none when the material has no volume term); corner c is the
/// tet's c-th point.
class VolumeFamily
{
public:
  static constexpr int kCorners = 4;
  using StepData = std::array<Vec3, 4>; ///< g0: the volume gradients at x0
  struct AtX
  {
    std::array<Vec3, 4> gradient; ///< g = dV/dx_c at x [m^2]
    double scale;                 ///< K (V - V0) [N/m^2]
    double dampingScale;          ///< Kd r [N/m^2]
  };
  using HessianData = double; ///< K + Kd / h [N/m^5]

  VolumeFamily(const Topology& topology, const ElementConstants& constants)
    : Topo(&topology)
    , Constants(&constants)
  {
  }

  std::size_t size() const { return Constants->hasVolumeTerm ? Topo->tets.size() : 0; }
  std::array<std::int32_t, 4> corners(std::size_t t) const { return Topo->tets[t]; }
  /// The mesh edge between corners a and b (a != b).
  std::int32_t edgeBetween(std::size_t t, int a, int b) const
  {
    return tetEdgeBetween(*Topo, t, a, b);
  }

  /// visit(tet, corner) for each tet corner at `vertex`, in Topology::vertexTetCorners' order.
  template <class Visit>
  void forEachCorner(std::int32_t vertex, Visit&& visit) const
  {
    if (Constants->hasVolumeTerm)
    {
      forEachTetCorner(*Topo, vertex, visit);
    }
  }

  StepData stepData(std::size_t t, const std::vector<Vec3>& x0) const
  {
    const Tet& tet = Topo->tets[t];
    return tetVolumeGradients(x0[tet[0]], x0[tet[1]], x0[tet[2]], x0[tet[3]]);
  }

  double evaluate(std::size_t t, const std::vector<Vec3>& x, const StepStart& start,
    const StepData& g0, AtX& out) const
  {
    const Tet& tet = Topo->tets[t];
    const ElementConstants& c = *Constants;
    out.gradient = tetVolumeGradients(x[tet[0]], x[tet[1]], x[tet[2]], x[tet[3]]);
    const double dv =
      signedTetVolume(x[tet[0]], x[tet[1]], x[tet[2]], x[tet[3]]) - c.restVolume[t];
    double rate = 0.0; // dV/dt linearized at the step's start, (g0 . dx) / h
    for (int k = 0; k < 4; ++k)
    {
      rate += g0[static_cast<std::size_t>(k)].dot(x[tet[k]] - start.x0[tet[k]]);
    }
    rate /= start.h;
    out.scale = c.volumeStiffness[t] * dv;
    out.dampingScale = c.volumeDamping[t] * rate;
    return 0.5 * c.volumeStiffness[t] * dv * dv + 0.5 * c.volumeDamping[t] * start.h * rate * rate;
  }

  Vec3 cornerGradient(const StepData& g0, const AtX& at, int corner) const
  {
    const auto c = static_cast<std::size_t>(corner);
    return at.scale * at.gradient[c] + at.dampingScale * g0[c];
  }

  HessianData hessianData(std::size_t t, const std::vector<Vec3>&, const StepStart& start,
    const StepData&, const AtX&) const
  {
    // Volume damping's exact Hessian is (Kd / h) g0 g0^T with the step's initial gradients;
    // g differs from g0 by one step's deformation, so (K + Kd / h) g g^T halves the outer
    // products at the cost of an O(h) error in a term Newton only needs approximately (the
    // gradient, and so the answer, keeps g0).
    return Constants->volumeStiffness[t] + Constants->volumeDamping[t] / start.h;
  }

  Mat3 hessianBlock(const StepData&, const AtX& at, const HessianData& weight, int a, int b) const
  {
    const Vec3 wg = weight * at.gradient[static_cast<std::size_t>(a)];
    return wg * at.gradient[static_cast<std::size_t>(b)].transpose();
  }

  /// Row norm bound at rest: K |g_a| sum_b |g_b| >= sum_b |K g_a g_b^T|.
  double stiffnessBound(std::size_t t, int a, const std::vector<Vec3>& rest) const
  {
    const std::array<Vec3, 4> g = stepData(t, rest);
    const double sum = g[0].norm() + g[1].norm() + g[2].norm() + g[3].norm();
    return Constants->volumeStiffness[t] * g[static_cast<std::size_t>(a)].norm() * sum;
  }

private:
  const Topology* Topo;
  const ElementConstants* Constants;
};

/// The network as a material model: its springs, then its volume terms (the order of their
/// sums in the incremental potential).
class SpringNetwork
{
public:
  SpringNetwork(const Topology& topology, const ElementConstants& constants)
    : Springs(topology, constants)
    , Volumes(topology, constants)
  {
  }

  std::tuple<const SpringFamily&, const VolumeFamily&> families() const
  {
    return { Springs, Volumes };
  }

private:
  SpringFamily Springs;
  VolumeFamily Volumes;
};

static_assert(ElementFamily<SpringFamily>);
static_assert(ElementFamily<VolumeFamily>);
static_assert(ElementModel<SpringNetwork>);

} // namespace softbody
