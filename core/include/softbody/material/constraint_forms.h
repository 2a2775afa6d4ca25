// Each continuum law (isotropic_elasticity.h) written as two constraints on a tet's deformation
// gradient F, for XPBD (Macklin and Mueller 2021, "A Constraint-based Formulation of Stable
// Neo-Hookean Materials"):
//
//   V0 Psi(F) = V0 kD / 2 C_D(F)^2 + V0 kH / 2 (J - Jrest)^2 + const,    J = det F
//
// so a tet's deviatoric constraint C_D has compliance 1 / (kD V0) and its hydrostatic one
// C_H = J - Jrest has 1 / (kH V0). The constraints' energy is the law's own, so XPBD's rest state
// comes to the mass-spring model's Static solve of the same law as its substep shrinks.
//
//   Corotated   Psi = mu |F - R|^2 + lambda / 2 (J - 1)^2
//               C_D = |F - R|,  kD = 2 mu;  Jrest = 1, kH = lambda.  dC_D/dF = (F - R) / C_D
//               (R the rotation of F's rotation-variant SVD, as the mass-spring model's).
//   Stable Neo-Hookean (with the law's re-parameterized mu, lambda, alpha = 1 + 3 mu / (4 lambda))
//               Psi = mu / 2 (I_C - 3) - mu / 2 log(I_C + 1) + lambda / 2 (J - alpha)^2 + const
//                   = mu / 2 q(F) + (lambda - mu / 4) / 2 (J - 1)^2 + const, with
//               q = I_C - log(I_C + 1) - 3 + log 4 - 3/2 (J - 1) + 1/4 (J - 1)^2,
//               C_D = sqrt(q),  kD = mu;  Jrest = 1, kH = lambda - mu / 4.
//
// Both constraints vanish at rest, as Corotated's do. Macklin and Mueller's C_D = |F| (the log
// dropped) and C_H = J - alpha are not zero at rest, nor is the same with the log kept under the
// root: the two then hold each other in balance with large multipliers, and XPBD, which builds
// its multipliers anew every step along the iterates' path, turns the gradients' change over
// that path into a force error times that prestress (with the log under the root, a soft
// hanging bar at one substep was off by more than its own sag). Moving the linear term 3/4 mu (J - 1)
// and a quarter of mu's worth of (J - 1)^2 from the hydrostatic part into q makes both parts
// stationary at rest; q >= 0 everywhere and is zero only on rotations (checked on 12 million
// random singular values, and q >= 0.023 times the squared distance from the nearest rotation;
// with 1/8 instead of 1/4 it goes negative). kH >= 0 needs nu >= -1/2.
#pragma once

#include "softbody/material/elastic_laws.h"

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
  static double hydrostaticStiffness(const LameParameters& p) { return p.lambda - 0.25 * p.mu; }
  static double restJ(const LameParameters&) { return 1.0; }
  static DeviatoricConstraint deviatoric(const Mat3& f)
  {
    DeviatoricConstraint c;
    const double ic = f.squaredNorm();
    Mat3 cof;
    cof.col(0) = f.col(1).cross(f.col(2));
    cof.col(1) = f.col(2).cross(f.col(0));
    cof.col(2) = f.col(0).cross(f.col(1));
    const double jm1 = f.col(0).dot(cof.col(0)) - 1.0;
    const double q = ic - std::log1p(ic) - 3.0 + std::log(4.0) - 1.5 * jm1 + 0.25 * jm1 * jm1;
    c.value = std::sqrt(std::max(0.0, q));
    // Zero on rotations, where the direction is undefined and nothing is asked.
    if (c.value > 0.0)
    {
      c.gradient = (0.5 / c.value) * ((2.0 * ic / (ic + 1.0)) * f + (0.5 * jm1 - 1.5) * cof);
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
  return withElasticLaw(model, [&](auto law) { return ConstraintForm<decltype(law)>::deviatoric(f); });
}

} // namespace softbody
