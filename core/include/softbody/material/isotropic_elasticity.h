// Isotropic hyperelastic energy densities Psi(F) of the deformation gradient F, written in F's
// singular values (the form of Smith, de Goes and Kim 2019, "Analytic Eigensystems for
// Isotropic Distortion Energies", and of Kim and Eberle 2020, "Dynamic Deformables"):
//
//   F = U diag(s) V^T (rotation-variant SVD: U, V rotations, s3 < 0 for an inverted element)
//   P = dPsi/dF = U diag(dPsi/ds) V^T
//   dP/dF has nine eigenpairs, every one in closed form:
//     three scaling modes  U diag(a) V^T, (a, value) the eigenpairs of d2Psi/ds2 (3x3)
//     three twist modes    U (e_i e_j^T - e_j e_i^T) V^T / sqrt 2,  (psi_i + psi_j) / (s_i + s_j)
//     three flip modes     U (e_i e_j^T + e_j e_i^T) V^T / sqrt 2,  (psi_i - psi_j) / (s_i - s_j)
// so the exact PSD projection of dP/dF clamps the negative values of those nine and sums the
// rest (no 9x9 eigensolver). Each law writes the twist and flip values without the division,
// so they stay exact at repeated singular values (the rest shape has s = 1, 1, 1).
//
// The two laws, with mu and lambda the Lame parameters of the law:
//   Corotated (fixed corotated, Stomakhin et al. 2012)
//     Psi = mu |F - R|^2 + lambda / 2 (J - 1)^2,    J = det F = s1 s2 s3
//   Stable Neo-Hookean (Smith, de Goes and Kim 2018)
//     Psi = mu / 2 (I_C - 3) + lambda / 2 (J - alpha)^2 - mu / 2 log(I_C + 1) - Psi(I),
//     I_C = |F|^2, alpha = 1 + 3 mu / (4 lambda): zero stress at rest. Its small-strain limit is
//     linear elasticity with mu_lin = 3/4 mu and lambda_lin = lambda - 5/8 mu, so the law takes
//     mu = 4/3 mu_lin, lambda = lambda_lin + 5/6 mu_lin (the paper's Sec. 3.4) and the E and nu a
//     user types mean what they mean in a linear model. Both are finite for flat (J = 0) and
//     inverted tets and push them back.
#pragma once

#include "softbody/common/geometry.h"

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>

namespace softbody
{

using Mat3 = Eigen::Matrix3d;
using Vec9 = Eigen::Matrix<double, 9, 1>;
using Mat9 = Eigen::Matrix<double, 9, 9>;

/// The Lame parameters of a linear isotropic solid [Pa].
struct LameParameters
{
  double mu = 0.0;     ///< shear modulus
  double lambda = 0.0; ///< Lame's first parameter
};

/// mu = E / (2 (1 + nu)), lambda = E nu / ((1 + nu)(1 - 2 nu)), for nu in (-1, 0.5).
inline LameParameters lameFromYoung(double youngsModulus, double poissonRatio)
{
  const double e = youngsModulus, nu = poissonRatio;
  return { e / (2.0 * (1.0 + nu)), e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)) };
}

/// The rotation-variant SVD of F: U and V proper rotations, s sorted by magnitude with only
/// s(2) ever negative (an inverted F). R = U V^T is F's nearest rotation.
struct RotationVariantSvd
{
  Mat3 u, v;
  Vec3 s;
};

/// The same from Eigen's JacobiSVD: accurate for every F, and iterative (its sweeps grow with
/// how far F's singular directions are from the axes, so rotated real meshes cost the most).
inline RotationVariantSvd rotationVariantSvdJacobi(const Mat3& f)
{
  const Eigen::JacobiSVD<Mat3> svd(f, Eigen::ComputeFullU | Eigen::ComputeFullV);
  RotationVariantSvd out{ svd.matrixU(), svd.matrixV(), svd.singularValues() };
  if (out.u.determinant() < 0.0)
  {
    out.u.col(2) *= -1.0;
    out.s(2) *= -1.0;
  }
  if (out.v.determinant() < 0.0)
  {
    out.v.col(2) *= -1.0;
    out.s(2) *= -1.0;
  }
  return out;
}

/// The largest |U diag(s) V^T - F| and |V^T V - I| entries, relative to |F|, a closed-form
/// SVD may leave before it is set aside for JacobiSVD's.
constexpr double kClosedFormSvdTolerance = 1.0e-14;

/// The rotation-variant SVD in closed form, where it is accurate: V from the eigenvectors of
/// F^T F (Eigen's direct 3x3 solver, no iteration), U's first two columns from F V / s made
/// orthonormal, the third their cross product (so U is proper even for an inverted F, whose
/// s(2) then comes out negative). False where the result does not reproduce F to
/// kClosedFormSvdTolerance (a nearly flat F, whose second singular value the eigenvalues of
/// F^T F cannot resolve, or eigenvectors the direct solver loses near repeated eigenvalues).
inline bool rotationVariantSvdClosedForm(const Mat3& f, RotationVariantSvd& out)
{
  Eigen::SelfAdjointEigenSolver<Mat3> eigen;
  eigen.computeDirect(f.transpose() * f); // eigenvalues ascending
  const Mat3& w = eigen.eigenvectors();
  out.v.col(0) = w.col(2);
  out.v.col(1) = w.col(1);
  out.v.col(2) = w.col(0);
  if (out.v.determinant() < 0.0)
  {
    out.v.col(2) *= -1.0;
  }
  const Vec3 a = f * out.v.col(0), b = f * out.v.col(1);
  const double s0 = a.norm();
  if (!(s0 > 0.0) || !std::isfinite(s0))
  {
    return false;
  }
  const Vec3 u0 = a / s0;
  const Vec3 b1 = b - u0.dot(b) * u0;
  const double s1 = b1.norm();
  if (!(s1 > 1.0e-6 * s0))
  {
    return false;
  }
  out.u.col(0) = u0;
  out.u.col(1) = b1 / s1;
  out.u.col(2) = u0.cross(out.u.col(1));
  out.s = Vec3(s0, s1, out.u.col(2).dot(f * out.v.col(2)));
  const double scale = kClosedFormSvdTolerance * f.cwiseAbs().maxCoeff();
  return (out.u * out.s.asDiagonal() * out.v.transpose() - f).cwiseAbs().maxCoeff() <= scale &&
    (out.v.transpose() * out.v - Mat3::Identity()).cwiseAbs().maxCoeff() <= kClosedFormSvdTolerance &&
    out.s(0) >= out.s(1) - scale && out.s(1) >= std::abs(out.s(2)) - scale; // sorted, to rounding
}

/// The closed form where it is accurate, JacobiSVD where it is not (both give the same
/// factors up to the signs and bases a repeated singular value leaves free).
inline RotationVariantSvd rotationVariantSvd(const Mat3& f)
{
  RotationVariantSvd out;
  return rotationVariantSvdClosedForm(f, out) ? out : rotationVariantSvdJacobi(f);
}

/// Index of the singular value that is not i or j (pairs (0,1), (0,2), (1,2)).
constexpr int thirdIndex(int i, int j) { return 3 - i - j; }

/// Fixed corotated elasticity (see the header comment).
struct CorotatedLaw
{
  static constexpr const char* kName = "Corotated";
  /// The law's parameters for a linear solid's (the same: its small-strain limit is linear).
  static LameParameters fromLinear(const LameParameters& linear) { return linear; }

  static double energy(const Vec3& s, const LameParameters& p)
  {
    const double j = s(0) * s(1) * s(2);
    return p.mu * (s - Vec3::Ones()).squaredNorm() + 0.5 * p.lambda * (j - 1.0) * (j - 1.0);
  }
  /// dPsi/ds_k.
  static Vec3 gradient(const Vec3& s, const LameParameters& p)
  {
    const double j = s(0) * s(1) * s(2);
    const Vec3 others(s(1) * s(2), s(0) * s(2), s(0) * s(1)); // dJ/ds_k
    return 2.0 * p.mu * (s - Vec3::Ones()) + p.lambda * (j - 1.0) * others;
  }
  /// d2Psi/ds2.
  static Mat3 hessian(const Vec3& s, const LameParameters& p)
  {
    const double j = s(0) * s(1) * s(2);
    const Vec3 others(s(1) * s(2), s(0) * s(2), s(0) * s(1));
    Mat3 h = 2.0 * p.mu * Mat3::Identity() + p.lambda * others * others.transpose();
    h(0, 1) = h(1, 0) = h(0, 1) + p.lambda * (j - 1.0) * s(2);
    h(0, 2) = h(2, 0) = h(0, 2) + p.lambda * (j - 1.0) * s(1);
    h(1, 2) = h(2, 1) = h(1, 2) + p.lambda * (j - 1.0) * s(0);
    return h;
  }
  static double twist(const Vec3& s, int i, int j, const LameParameters& p)
  {
    // mu |F - R|^2 contributes 2 mu (1 - 2 / (s_i + s_j)), which is very negative for a
    // collapsing pair; the projection clamps it. The floor on the sum keeps it finite when both
    // singular values vanish.
    const double sum = std::max(s(i) + s(j), 1e-12);
    const double jac = s(0) * s(1) * s(2);
    return 2.0 * p.mu * (1.0 - 2.0 / sum) + p.lambda * (jac - 1.0) * s(thirdIndex(i, j));
  }
  static double flip(const Vec3& s, int i, int j, const LameParameters& p)
  {
    const double jac = s(0) * s(1) * s(2);
    return 2.0 * p.mu - p.lambda * (jac - 1.0) * s(thirdIndex(i, j));
  }
};

/// Stable Neo-Hookean elasticity (see the header comment); its parameters are the law's own,
/// made from a linear solid's by fromLinear().
struct StableNeoHookeanLaw
{
  static constexpr const char* kName = "Stable Neo-Hookean";
  static LameParameters fromLinear(const LameParameters& linear)
  {
    return { 4.0 / 3.0 * linear.mu, linear.lambda + 5.0 / 6.0 * linear.mu };
  }
  static double alpha(const LameParameters& p) { return 1.0 + 0.75 * p.mu / p.lambda; }

  static double energy(const Vec3& s, const LameParameters& p)
  {
    const double ic = s.squaredNorm();
    const double j = s(0) * s(1) * s(2);
    const double a = alpha(p);
    const double rest = 0.5 * p.lambda * (1.0 - a) * (1.0 - a) - 0.5 * p.mu * std::log(4.0);
    return 0.5 * p.mu * (ic - 3.0) + 0.5 * p.lambda * (j - a) * (j - a) -
      0.5 * p.mu * std::log(ic + 1.0) - rest;
  }
  static Vec3 gradient(const Vec3& s, const LameParameters& p)
  {
    const double ic = s.squaredNorm();
    const double j = s(0) * s(1) * s(2);
    const Vec3 others(s(1) * s(2), s(0) * s(2), s(0) * s(1));
    return p.mu * (1.0 - 1.0 / (ic + 1.0)) * s + p.lambda * (j - alpha(p)) * others;
  }
  /// Psi and P = mu (1 - 1 / (I_C + 1)) F + lambda (J - alpha) cof(F) straight from F.
  static double energyAndStressOf(const Mat3& f, const LameParameters& p, Mat3& stress)
  {
    const double ic = f.squaredNorm();
    Mat3 cofactor; // J F^-T, column by column
    cofactor.col(0) = f.col(1).cross(f.col(2));
    cofactor.col(1) = f.col(2).cross(f.col(0));
    cofactor.col(2) = f.col(0).cross(f.col(1));
    const double j = f.col(0).dot(cofactor.col(0));
    const double a = alpha(p);
    stress = p.mu * (1.0 - 1.0 / (ic + 1.0)) * f + p.lambda * (j - a) * cofactor;
    const double rest = 0.5 * p.lambda * (1.0 - a) * (1.0 - a) - 0.5 * p.mu * std::log(4.0);
    return 0.5 * p.mu * (ic - 3.0) + 0.5 * p.lambda * (j - a) * (j - a) -
      0.5 * p.mu * std::log(ic + 1.0) - rest;
  }
  static Mat3 hessian(const Vec3& s, const LameParameters& p)
  {
    const double ic = s.squaredNorm();
    const double j = s(0) * s(1) * s(2);
    const double c = j - alpha(p);
    const Vec3 others(s(1) * s(2), s(0) * s(2), s(0) * s(1));
    Mat3 h = p.mu * (1.0 - 1.0 / (ic + 1.0)) * Mat3::Identity() +
      (2.0 * p.mu / ((ic + 1.0) * (ic + 1.0))) * s * s.transpose() +
      p.lambda * others * others.transpose();
    h(0, 1) = h(1, 0) = h(0, 1) + p.lambda * c * s(2);
    h(0, 2) = h(2, 0) = h(0, 2) + p.lambda * c * s(1);
    h(1, 2) = h(2, 1) = h(1, 2) + p.lambda * c * s(0);
    return h;
  }
  static double twist(const Vec3& s, int i, int j, const LameParameters& p)
  {
    const double ic = s.squaredNorm();
    const double jac = s(0) * s(1) * s(2);
    return p.mu * (1.0 - 1.0 / (ic + 1.0)) + p.lambda * (jac - alpha(p)) * s(thirdIndex(i, j));
  }
  static double flip(const Vec3& s, int i, int j, const LameParameters& p)
  {
    const double ic = s.squaredNorm();
    const double jac = s(0) * s(1) * s(2);
    return p.mu * (1.0 - 1.0 / (ic + 1.0)) - p.lambda * (jac - alpha(p)) * s(thirdIndex(i, j));
  }
};

template <class Law>
concept IsotropicLaw = requires(const Vec3& s, const LameParameters& p, int i) {
  { Law::energy(s, p) } -> std::same_as<double>;
  { Law::gradient(s, p) } -> std::same_as<Vec3>;
  { Law::hessian(s, p) } -> std::same_as<Mat3>;
  { Law::twist(s, i, i, p) } -> std::same_as<double>;
  { Law::flip(s, i, i, p) } -> std::same_as<double>;
  { Law::fromLinear(p) } -> std::same_as<LameParameters>;
};

/// vec(A) with the row-major index 3 r + c: the layout every 9x9 tensor here uses.
inline Vec9 flatten(const Mat3& a)
{
  Vec9 v;
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
    {
      v(3 * r + c) = a(r, c);
    }
  }
  return v;
}

/// The first Piola-Kirchhoff stress P = U diag(dPsi/ds) V^T [Pa].
template <IsotropicLaw Law>
Mat3 firstPiolaStress(const RotationVariantSvd& svd, const LameParameters& p)
{
  return svd.u * Law::gradient(svd.s, p).asDiagonal() * svd.v.transpose();
}

/// dP/dF from its nine eigenpairs in the singular frame: the scaling modes from the 3x3
/// `scaling` (d2Psi/ds2) and the twist and flip values of the pairs (0,1), (0,2), (1,2); with
/// `project`, the negative eigenvalues are clamped to zero (the exact PSD projection). [Pa]
inline Mat9 stressDerivativeFromModes(const RotationVariantSvd& svd, const Mat3& scaling,
  const Vec3& twists, const Vec3& flips, bool project)
{
  const auto keep = [&](double value) { return project ? std::max(value, 0.0) : value; };
  Mat9 dpdf = Mat9::Zero();
  const auto addMode = [&](double value, const Mat3& inSingularFrame) {
    if (value != 0.0)
    {
      const Vec9 q = flatten(svd.u * inSingularFrame * svd.v.transpose());
      dpdf.noalias() += value * q * q.transpose();
    }
  };
  // The iterative solver, not computeDirect: the closed-form 3x3 roots lose about half the
  // digits at the double eigenvalue 2 mu of every body at rest.
  const Eigen::SelfAdjointEigenSolver<Mat3> modes(scaling);
  for (int k = 0; k < 3; ++k)
  {
    addMode(keep(modes.eigenvalues()(k)), Mat3(modes.eigenvectors().col(k).asDiagonal()));
  }
  constexpr double kInvSqrt2 = 0.70710678118654752440;
  constexpr int kPairs[3][2] = { { 0, 1 }, { 0, 2 }, { 1, 2 } };
  for (int pair = 0; pair < 3; ++pair)
  {
    const int i = kPairs[pair][0], j = kPairs[pair][1];
    Mat3 twist = Mat3::Zero(), flip = Mat3::Zero();
    twist(i, j) = kInvSqrt2;
    twist(j, i) = -kInvSqrt2;
    flip(i, j) = flip(j, i) = kInvSqrt2;
    addMode(keep(twists(pair)), twist);
    addMode(keep(flips(pair)), flip);
  }
  return dpdf;
}

/// dP/dF of the law from its nine eigenpairs; with `project`, the PSD projection. [Pa]
template <IsotropicLaw Law>
Mat9 stressDerivative(const RotationVariantSvd& svd, const LameParameters& p, bool project)
{
  const Vec3& s = svd.s;
  const Vec3 twists(Law::twist(s, 0, 1, p), Law::twist(s, 0, 2, p), Law::twist(s, 1, 2, p));
  const Vec3 flips(Law::flip(s, 0, 1, p), Law::flip(s, 0, 2, p), Law::flip(s, 1, 2, p));
  return stressDerivativeFromModes(svd, Law::hessian(s, p), twists, flips, project);
}

/// The same for a tet under the nodal-averaged pressure (nodal_pressure.h): the law without its
/// volumetric term lambda / 2 (J - 1)^2, plus `pressure` J, the tet's share of the points'
/// pressure (its curvature in J alone; the points' coupling is apart). [Pa]
template <IsotropicLaw Law>
Mat9 stressDerivativeWithPressure(const RotationVariantSvd& svd, const LameParameters& p,
  double pressure, bool project)
{
  const Vec3& s = svd.s;
  const double shift = pressure - p.lambda * (s(0) * s(1) * s(2) - 1.0); // pressure - the tet's own
  const Vec3 others(s(1) * s(2), s(0) * s(2), s(0) * s(1));
  Mat3 scaling = Law::hessian(s, p) - p.lambda * others * others.transpose();
  scaling(0, 1) = scaling(1, 0) = scaling(0, 1) + shift * s(2);
  scaling(0, 2) = scaling(2, 0) = scaling(0, 2) + shift * s(1);
  scaling(1, 2) = scaling(2, 1) = scaling(1, 2) + shift * s(0);
  const Vec3 twists(Law::twist(s, 0, 1, p) + shift * s(2), Law::twist(s, 0, 2, p) + shift * s(1),
    Law::twist(s, 1, 2, p) + shift * s(0));
  const Vec3 flips(Law::flip(s, 0, 1, p) - shift * s(2), Law::flip(s, 0, 2, p) - shift * s(1),
    Law::flip(s, 1, 2, p) - shift * s(0));
  return stressDerivativeFromModes(svd, scaling, twists, flips, project);
}

/// The Hessian of the viscous potential of tet_elasticity.h, dF -> C : sym(G^T dF) seen from
/// the frame G (the step's F0): the 9x9 matrix of 2 mu sym(G^T dF) : sym(G^T dF') +
/// lambda tr(G^T dF) tr(G^T dF'), positive semi-definite for any G [Pa].
inline Mat9 viscousTensor(const Mat3& frame, const LameParameters& p)
{
  Mat9 c;
  Eigen::Matrix<double, 9, 9> sym; // columns: vec(sym(G^T E_m)) for unit matrices E_m
  Vec9 trace;
  for (int m = 0; m < 9; ++m)
  {
    Mat3 e = Mat3::Zero();
    e(m / 3, m % 3) = 1.0;
    const Mat3 local = frame.transpose() * e;
    sym.col(m) = flatten(0.5 * (local + local.transpose()));
    trace(m) = local.trace();
  }
  c.noalias() = 2.0 * p.mu * sym.transpose() * sym;
  c.noalias() += p.lambda * trace * trace.transpose();
  return c;
}

/// Psi(F) [Pa] and, in `stress`, P(F): from the law's closed form in F where it has one (no
/// SVD: Stable Neo-Hookean is polynomial in F but for its log term), else from the SVD.
template <IsotropicLaw Law>
double energyAndStress(const Mat3& f, const LameParameters& p, Mat3& stress)
{
  if constexpr (requires { Law::energyAndStressOf(f, p, stress); })
  {
    return Law::energyAndStressOf(f, p, stress);
  }
  else
  {
    const RotationVariantSvd svd = rotationVariantSvd(f);
    stress = firstPiolaStress<Law>(svd, p);
    return Law::energy(svd.s, p);
  }
}

} // namespace softbody
