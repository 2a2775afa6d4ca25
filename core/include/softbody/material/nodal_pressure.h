// Nodal-averaged pressure on linear tets: the continuum models without volumetric locking.
//
// A linear tet has one volume ratio J, so a nearly incompressible material asks every tet to
// keep its own volume: with about five tets per point that is more constraints than the mesh has
// motions, and the body locks (too stiff in bending by 13 % at nu = 0.45 on a cantilever of
// 15k tets, and not converging at second order). Averaging the volumetric part over the tets
// around each point (Bonet and Burton 1998, "A simple average nodal pressure tetrahedral element
// for incompressible and nearly incompressible dynamic explicit applications"; LS-DYNA's
// nodal-pressure tet) leaves one volume constraint per point:
//
//   E = sum_t V0_t [Psi(F_t) - lambda_t / 2 (J_t - 1)^2]  +  sum_a V_a lambda_a / 2 (Jbar_a - 1)^2
//
//   V_a    = sum over a's tets of V0_t / 4                 (the point's share of rest volume)
//   Jbar_a = sum over a's tets of V0_t J_t / 4 / V_a       (its current over rest volume)
//   lambda_a = the rest-volume-weighted mean of its tets' lambda
//
// Both laws hold the volumetric term lambda / 2 (J - 1)^2 (Stable Neo-Hookean's
// lambda / 2 (J - alpha)^2 is that plus a term linear in J times mu), so the tet keeps its law's
// shear part and the point takes the bulk. An affine motion gives every tet and point the same
// J, so the patch test still holds. The force on a tet's corner is its law's with the tet's
// own pressure lambda_t (J_t - 1) replaced by pbar_t, the mean of p_a = lambda_a (Jbar_a - 1)
// over its four corners. The Hessian is the tets' part (projected from the laws' eigensystems
// with pbar_t in place of the tet's pressure) plus the coupling
//   sum_a V_a lambda_a grad Jbar_a grad Jbar_a^T,
// positive semi-definite, which joins every two points of a point's tets: beyond the mesh's
// edges, so BlockSparseMatrix carries it as a product (its diagonal blocks assembled).
#pragma once

#include "softbody/common/geometry.h"
#include "softbody/mesh/topology.h"

#include <Eigen/Core>

#include <vector>

namespace softbody
{

class BlockSparseMatrix;
struct TetElasticConstants;

/// What the averaging needs of the rest shape, per point.
struct NodalPressureConstants
{
  std::vector<double> volume; ///< V_a [m^3]; 0 for a point in no tet
  std::vector<double> lambda; ///< lambda_a [Pa]
};

NodalPressureConstants computeNodalPressureConstants(const Topology& topology,
  const std::vector<double>& restVolume, const std::vector<double>& tetLambda);

/// The averaged volume ratios and pressures at one set of positions.
struct NodalPressureField
{
  std::vector<double> tetRatio;      ///< J_t
  std::vector<double> pointRatio;    ///< Jbar_a
  std::vector<double> tetPressure;   ///< pbar_t [Pa]
  double energy = 0.0;               ///< sum_a V_a lambda_a / 2 (Jbar_a - 1)^2 [J]
};

/// Fills `field` at positions x (three passes: tets, points, tets; sums in a fixed order).
void evaluateNodalPressure(const Topology& topology, const TetElasticConstants& constants,
  const std::vector<Vec3>& x, NodalPressureField& field);

/// Adds the coupling sum_a V_a lambda_a grad Jbar_a grad Jbar_a^T at x (the x `field` was
/// evaluated at) to `hessian`: its diagonal blocks into the matrix's, the rest as the matrix's
/// coupling product. Rows where `active` is 0 take no part.
void addNodalPressureCoupling(const Topology& topology, const TetElasticConstants& constants,
  const std::vector<Vec3>& x, const std::vector<char>& active, BlockSparseMatrix& hessian);

/// The cofactor matrix J F^-T of F (defined for flat and inverted F).
inline Eigen::Matrix3d cofactorOf(const Eigen::Matrix3d& f)
{
  Eigen::Matrix3d cofactor;
  cofactor.col(0) = f.col(1).cross(f.col(2));
  cofactor.col(1) = f.col(2).cross(f.col(0));
  cofactor.col(2) = f.col(0).cross(f.col(1));
  return cofactor;
}

} // namespace softbody
