// PBD/XPBD constraint batches: one contiguous batch per constraint type, each with the same small
// interface the solvers are written against:
//   Arity                      particles per constraint
//   size()                     number of constraints
//   particles(c)               their indices
//   active(c)                  false for broken links (and the tets they belonged to)
//   project(c, x, w)           the kernel of pbd_kernels.h with this constraint's data
//   lambda[c], params[c]       Lagrange multiplier (reset each step) and per-step constants
#pragma once

#include "softbody/common/permutation.h"
#include "softbody/pbd/pbd_kernels.h"
#include "softbody/pbd/pbd_tet_elastic_kernel.h"

#include <array>
#include <cstdint>
#include <vector>

namespace softbody
{

/// Distance links: tet edges and explicit links (cloth, lattices). They may be plastic (the rest
/// length creeps) and breakable, so rest lengths and broken flags are part of the state.
struct DistanceBatch
{
  static constexpr int Arity = 2;
  std::vector<std::array<std::int32_t, 2>> ends;
  std::vector<double> originalRest;   ///< rest length at t = 0 [m]
  std::vector<double> rest;           ///< current rest length [m] (plastic flow changes it)
  std::vector<double> stiffnessScale; ///< per-link factor on the batch stiffness (cloth diagonals)
  std::vector<double> compliance;     ///< XPBD from elasticity: per-link alpha [m/N]; else empty
  std::vector<unsigned char> broken;
  DistanceKind kind = DistanceKind::Equality;
  std::vector<double> lambda;
  std::vector<ProjectionParameters> params;

  std::size_t size() const { return ends.size(); }
  const std::int32_t* particles(std::size_t c) const { return ends[c].data(); }
  bool active(std::size_t c) const { return broken[c] == 0; }
  Projection<2> project(std::size_t c, const std::vector<Vec3>& x, const std::vector<double>& w) const
  {
    const auto& e = ends[c];
    return projectDistance(x[e[0]], x[e[1]], w[e[0]], w[e[1]], rest[c], kind, lambda[c], params[c]);
  }
  /// Every per-link array stored in `order` (link s is the old link order[s]).
  void storeInOrder(const std::vector<std::int32_t>& order)
  {
    softbody::storeInOrder(ends, order);
    softbody::storeInOrder(originalRest, order);
    softbody::storeInOrder(rest, order);
    softbody::storeInOrder(stiffnessScale, order);
    softbody::storeInOrder(compliance, order);
    softbody::storeInOrder(broken, order);
    softbody::storeInOrder(lambda, order);
    softbody::storeInOrder(params, order);
  }
};

/// Tet volumes toward their rest volumes.
struct VolumeBatch
{
  static constexpr int Arity = 4;
  std::vector<Tet> tets;
  std::vector<double> restVolume; ///< [m^3], positive (tets are oriented positively)
  std::vector<double> compliance; ///< XPBD from elasticity: per-tet alpha [m^3/Pa] (inf: none)
  std::vector<unsigned char> broken; ///< a tet with a broken edge no longer holds its volume
  std::vector<double> lambda;
  std::vector<ProjectionParameters> params;

  std::size_t size() const { return tets.size(); }
  const std::int32_t* particles(std::size_t c) const { return tets[c].data(); }
  bool active(std::size_t c) const { return broken[c] == 0; }
  Projection<4> project(std::size_t c, const std::vector<Vec3>& x, const std::vector<double>& w) const
  {
    const Tet& t = tets[c];
    return projectTetVolume({ x[t[0]], x[t[1]], x[t[2]], x[t[3]] },
      { w[t[0]], w[t[1]], w[t[2]], w[t[3]] }, restVolume[c], lambda[c], params[c]);
  }
  /// Every per-tet array stored in `order` (tet s is the old tet order[s]).
  void storeInOrder(const std::vector<std::int32_t>& order)
  {
    softbody::storeInOrder(tets, order);
    softbody::storeInOrder(restVolume, order);
    softbody::storeInOrder(compliance, order);
    softbody::storeInOrder(broken, order);
    softbody::storeInOrder(lambda, order);
    softbody::storeInOrder(params, order);
  }
};

/// Tets of a continuum law (Corotated, Stable Neo-Hookean): each tet's deviatoric and
/// hydrostatic constraints, projected together (pbd_tet_elastic_kernel.h). Stored in the same
/// order as the VolumeBatch of the same tets, which then holds their rest volumes and broken
/// flags without being solved, so tet t is the same tet in both.
struct TetElasticBatch
{
  static constexpr int Arity = 4;
  MaterialModel model = MaterialModel::StableNeoHookean;
  std::vector<Tet> tets;
  std::vector<std::array<Vec3, 4>> shapeGradients; ///< G_k [1/m]
  std::vector<double> restJ;                       ///< J the hydrostatic constraint holds
  std::vector<double> deviatoricCompliance;        ///< 1 / (kD V0) [1/J]
  std::vector<double> hydrostaticCompliance;       ///< 1 / (kH V0) [1/J]; inf: no bulk term
  std::vector<TetElasticMultipliers> lambda;
  std::vector<TetElasticParameters> params;

  std::size_t size() const { return tets.size(); }
  const std::int32_t* particles(std::size_t c) const { return tets[c].data(); }
  bool active(std::size_t) const { return true; }
  Projection<4, TetElasticMultipliers> project(
    std::size_t c, const std::vector<Vec3>& x, const std::vector<double>& w) const
  {
    const Tet& t = tets[c];
    return projectTetElastic({ x[t[0]], x[t[1]], x[t[2]], x[t[3]] },
      { w[t[0]], w[t[1]], w[t[2]], w[t[3]] }, shapeGradients[c], model, restJ[c], lambda[c], params[c]);
  }
  void storeInOrder(const std::vector<std::int32_t>& order)
  {
    softbody::storeInOrder(tets, order);
    softbody::storeInOrder(shapeGradients, order);
    softbody::storeInOrder(restJ, order);
    softbody::storeInOrder(deviatoricCompliance, order);
    softbody::storeInOrder(hydrostaticCompliance, order);
    softbody::storeInOrder(lambda, order);
    softbody::storeInOrder(params, order);
  }
};

/// Soft attachments of particles to fixed targets (pins that are not infinitely stiff).
struct AttachmentBatch
{
  static constexpr int Arity = 1;
  std::vector<std::int32_t> particle;
  std::vector<Vec3> target;
  std::vector<double> lambda;
  std::vector<ProjectionParameters> params;

  std::size_t size() const { return particle.size(); }
  const std::int32_t* particles(std::size_t c) const { return &particle[c]; }
  bool active(std::size_t) const { return true; }
  Projection<1> project(std::size_t c, const std::vector<Vec3>& x, const std::vector<double>& w) const
  {
    const std::int32_t i = particle[c];
    return projectAttachment(x[i], w[i], target[c], lambda[c], params[c]);
  }
};

} // namespace softbody
