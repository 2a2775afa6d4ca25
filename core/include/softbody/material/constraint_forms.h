// Each continuum law (isotropic_elasticity.h) written as two constraints on a tet's deformation
// gradient F, for XPBD (Macklin and Mueller 2021, "A Constraint-based Formulation of Stable
// Neo-Hookean Materials"):
//
//   V0 Psi(F) = V0 kD / 2 C_D(F)^2 + V0 kH / 2 (J - Jrest)^2 + const,    J = det F
//
// so a tet's deviatoric constraint C_D has compliance 1 / (kD V0) and its hydrostatic one
// C_H = J - Jrest has 1 / (kH V0). A converged XPBD step then minimizes exactly the incremental
// potential of the law's own energy: XPBD rests where the mass-spring model's Static solve of the
// same law does, and takes (undamped) Implicit Euler's step.
//
//   Corotated   Psi = mu |F - R|^2 + lambda / 2 (J - 1)^2
//               C_D = |F - R|,  kD = 2 mu;  Jrest = 1, kH = lambda.  dC_D/dF = (F - R) / C_D
//               (R the rotation of F's rotation-variant SVD, as the mass-spring model's).
//   Stable Neo-Hookean (with the law's re-parameterized mu, lambda, alpha)
//               Psi = mu / 2 (I_C - 3) - mu / 2 log(I_C + 1) + lambda / 2 (J - alpha)^2 + const
//               C_D = sqrt(I_C - log(I_C + 1)),  kD = mu;  Jrest = alpha, kH = lambda.
//               dC_D/dF = (1 - 1 / (I_C + 1)) F / C_D.
//
// Macklin and Mueller drop the log term and take C_D = sqrt(I_C); keeping it under the root
// (I_C - log(I_C + 1) > 0 for every F but F = 0, 3 - log 4 at rest) keeps C_D smooth and makes
// the constraints' energy the one the other solvers minimize, not a neighbouring law.
#pragma once

#include "softbody/material/isotropic_elasticity.h"
#include "softbody/material/material.h"

#include <cmath>

namespace softbody
{

/// The deviatoric constraint's value C_D(F) and its derivative dC_D/dF.
struct DeviatoricConstraint
{
  double value = 0.0;
  Mat3 gradient = Mat3::Zero();
};

/// A continuum law's constraint split (see the header comment).
template <class Law>
struct ConstraintForm;

template <>
struct ConstraintForm<CorotatedLaw>
{
  static double deviatoricStiffness(const LameParameters& p) { return 2.0 * p.mu; }
  static double hydrostaticStiffness(const LameParameters& p) { return p.lambda; }
  static double restJ(const LameParameters&) { return 1.0; }
  static DeviatoricConstraint deviatoric(const Mat3& f)
  {
    const RotationVariantSvd svd = rotationVariantSvd(f);
    DeviatoricConstraint c;
    const Mat3 away = f - svd.u * svd.v.transpose();
    c.value = away.norm();
    // At C_D = 0 (F a rotation) the constraint is satisfied and its direction undefined: the
    // zero gradient asks for nothing, as a zero-length attachment does.
    if (c.value > 0.0)
    {
      c.gradient = away / c.value;
    }
    return c;
  }
};

template <>
struct ConstraintForm<StableNeoHookeanLaw>
{
  static double deviatoricStiffness(const LameParameters& p) { return p.mu; }
  static double hydrostaticStiffness(const LameParameters& p) { return p.lambda; }
  static double restJ(const LameParameters& p) { return StableNeoHookeanLaw::alpha(p); }
  static DeviatoricConstraint deviatoric(const Mat3& f)
  {
    DeviatoricConstraint c;
    const double ic = f.squaredNorm();
    c.value = std::sqrt(std::max(0.0, ic - std::log1p(ic)));
    if (c.value > 0.0)
    {
      c.gradient = (ic / (ic + 1.0) / c.value) * f;
    }
    return c;
  }
};

/// J's derivative dJ/dF = cof(F), column by column.
inline Mat3 cofactor(const Mat3& f)
{
  Mat3 c;
  c.col(0) = f.col(1).cross(f.col(2));
  c.col(1) = f.col(2).cross(f.col(0));
  c.col(2) = f.col(0).cross(f.col(1));
  return c;
}

/// The deviatoric constraint of `model` (a continuum one), chosen per call: a branch per tet is
/// nothing beside the constraint's own cost (an SVD for Corotated).
inline DeviatoricConstraint deviatoricConstraint(MaterialModel model, const Mat3& f)
{
  return model == MaterialModel::StableNeoHookean ? ConstraintForm<StableNeoHookeanLaw>::deviatoric(f)
                                                  : ConstraintForm<CorotatedLaw>::deviatoric(f);
}

} // namespace softbody
