// The XPBD kernel of a continuum tet (material/constraint_forms.h): its deviatoric constraint
// C_D(F) and its hydrostatic constraint C_H = J - Jrest, solved together as one 2 x 2 system
// (as Macklin and Mueller 2021 do):
//
//   (A + diag(aD, aH)) dLambda = -(C + diag(aD, aH) lambda),   A_ij = sum_k w_k g_ik . g_jk,
//   dx_k = w_k (g_Dk dLambda_D + g_Hk dLambda_H),              g_ik = (dC_i/dF) G_k,
//
// with aX = compliance / h^2 and G_k the tet's rest shape gradients (F = sum_k x_k G_k^T).
// Solved one after the other, the two fight: at rest both gradients are multiples of F = I, the
// deviatoric constraint asks the tet to shrink (Stable Neo-Hookean's C_D is not zero at rest)
// and the hydrostatic one to grow back, and for a stiff tet at a long step (aX small beside A)
// each undoes most of the other every iteration. Solved together they find the balance in one
// projection.
#pragma once

#include "softbody/material/constraint_forms.h"
#include "softbody/pbd/pbd_kernels.h"

#include <Eigen/Core>

#include <array>
#include <cmath>

namespace softbody
{

using TetElasticMultipliers = Eigen::Vector2d; ///< (lambda_D, lambda_H)

/// Per-tet constants of the coupled projection within one step.
struct TetElasticParameters
{
  double scale = 1.0;             ///< SOR's relaxation (1 for plain Gauss-Seidel and Jacobi)
  double alphaTildeDeviatoric = 0.0; ///< compliance / h^2 of C_D
  /// compliance / h^2 of C_H; infinite where the law has no bulk term (Corotated at nu = 0)
  double alphaTildeHydrostatic = 0.0;
};

inline Projection<4, TetElasticMultipliers> projectTetElastic(const std::array<Vec3, 4>& x,
  const std::array<double, 4>& w, const std::array<Vec3, 4>& shapeGradients, MaterialModel model,
  double restJ, const TetElasticMultipliers& lambda, const TetElasticParameters& p)
{
  Projection<4, TetElasticMultipliers> out;
  Mat3 f = x[0] * shapeGradients[0].transpose();
  for (std::size_t k = 1; k < 4; ++k)
  {
    f.noalias() += x[k] * shapeGradients[k].transpose();
  }
  const DeviatoricConstraint deviatoric = deviatoricConstraint(model, f);
  const Mat3 cof = cofactor(f);
  const double j = f.col(0).dot(cof.col(0));
  const bool hydrostatic = std::isfinite(p.alphaTildeHydrostatic);

  std::array<Vec3, 4> gD, gH;
  double add = 0.0, adh = 0.0, ahh = 0.0;
  for (std::size_t k = 0; k < 4; ++k)
  {
    gD[k] = deviatoric.gradient * shapeGradients[k];
    gH[k] = cof * shapeGradients[k];
    add += w[k] * gD[k].squaredNorm();
    adh += w[k] * gD[k].dot(gH[k]);
    ahh += w[k] * gH[k].squaredNorm();
  }
  const double rD = deviatoric.value + p.alphaTildeDeviatoric * lambda(0);
  const double rH = hydrostatic ? (j - restJ) + p.alphaTildeHydrostatic * lambda(1) : 0.0;
  out.residual = std::hypot(rD, rH);
  if (p.scale == 0.0)
  {
    out.residual = 0.0;
    return out;
  }
  add += p.alphaTildeDeviatoric;
  if (hydrostatic)
  {
    ahh += p.alphaTildeHydrostatic;
    const double det = add * ahh - adh * adh;
    // Positive whenever a compliance is (the Gram matrix is semi-definite): only a rigid
    // constraint on a flat tet or on pinned corners leaves nothing to solve.
    if (!(det > 0.0))
    {
      return out;
    }
    out.dLambda(0) = -p.scale * (ahh * rD - adh * rH) / det;
    out.dLambda(1) = -p.scale * (add * rH - adh * rD) / det;
  }
  else if (add > 0.0)
  {
    out.dLambda(0) = -p.scale * rD / add;
  }
  for (std::size_t k = 0; k < 4; ++k)
  {
    out.dx[k] = w[k] * (out.dLambda(0) * gD[k] + out.dLambda(1) * gH[k]);
  }
  return out;
}

} // namespace softbody
