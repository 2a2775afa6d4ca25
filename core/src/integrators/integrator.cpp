#include "softbody/integrators/integrator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <stdexcept>

namespace softbody
{
namespace
{

/// Spectral radius of a real 2x2 matrix [[a, b], [c, d]].
double spectralRadius2x2(double a, double b, double c, double d)
{
  const double halfTrace = 0.5 * (a + d);
  const double det = a * d - b * c;
  const double disc = halfTrace * halfTrace - det;
  if (disc < 0.0)
  {
    return std::sqrt(det); // complex pair: |lambda|^2 = det
  }
  const double root = std::sqrt(disc);
  return std::max(std::abs(halfTrace + root), std::abs(halfTrace - root));
}

// Each function below is the integrator's step matrix on (x, v) for x'' = -w^2 x - c x'.

double eulerRadius(double h, double omega, double c)
{
  // x' = x + h v, v' = v + h(-w^2 x - c v)
  const double w2 = omega * omega;
  return spectralRadius2x2(1.0, h, -h * w2, 1.0 - h * c);
}

double kickDriftRadius(double h, double omega, double c)
{
  // v' = v + h(-w^2 x - c v), x' = x + h v'. Leapfrog Verlet with a constant step is this
  // map on (x, v_{-1/2}).
  const double w2 = omega * omega;
  return spectralRadius2x2(1.0 - h * h * w2, h * (1.0 - h * c), -h * w2, 1.0 - h * c);
}

double backwardEulerRadius(double h, double omega, double c)
{
  // x' = x + h v', v' = v + h(-w^2 x' - c v'): A = [[1 + hc, h], [-h w^2, 1]] / D. Both
  // implicit integrators solve these equations when converged.
  const double w2 = omega * omega;
  const double d = 1.0 + h * c + h * h * w2;
  return spectralRadius2x2((1.0 + h * c) / d, h / d, -h * w2 / d, 1.0 / d);
}

double midpointRadius(double h, double omega, double c)
{
  // A = I + hJ + (hJ)^2 / 2 with J = [[0, 1], [-w^2, -c]], J^2 = [[-w^2, -c], [c w^2, c^2 - w^2]].
  const double w2 = omega * omega;
  const double h2 = 0.5 * h * h;
  return spectralRadius2x2(
    1.0 - h2 * w2, h - h2 * c, -h * w2 + h2 * c * w2, 1.0 - h * c + h2 * (c * c - w2));
}

double bdf2Radius(double h, double omega, double c)
{
  // BDF2 with a constant step on z' = J z: (3/2 - h lambda) zeta^2 - 2 zeta + 1/2 = 0 for each
  // eigenvalue lambda of J (the roots of s^2 + c s + w^2); the radius is the largest |zeta|.
  const std::complex<double> disc = std::sqrt(std::complex<double>(c * c - 4.0 * omega * omega));
  double radius = 0.0;
  for (const std::complex<double> lambda : { 0.5 * (-c + disc), 0.5 * (-c - disc) })
  {
    const std::complex<double> a = 1.5 - h * lambda;
    const std::complex<double> root = std::sqrt(4.0 - 2.0 * a);
    radius = std::max({ radius, std::abs((2.0 + root) / (2.0 * a)), std::abs((2.0 - root) / (2.0 * a)) });
  }
  return radius;
}

double staticRadius(double, double, double)
{
  // Every step lands on the equilibrium: nothing of the state before it survives.
  return 0.0;
}

using I = Integrator;
// clang-format off
constexpr std::array<IntegratorFacts, 9> kTable{ {
  // integrator            name                 order implicit symplectic evaluations
  //   staggered velocity, GPU, undamped reference, plan's element pass and linear solve, stability,
  //   embedded local error estimate
  { I::Euler,              "Euler",               1, false, false, 1,
    false, true,  I::EulerCromer,        nullptr,               nullptr,                eulerRadius, &kFirstOrderEstimate },
  { I::Midpoint,           "Midpoint",            2, false, false, 2,
    false, true,  I::Midpoint,           nullptr,               nullptr,                midpointRadius, nullptr },
  { I::Verlet,             "Verlet",              2, false, true,  1,
    true,  true,  I::Verlet,             nullptr,               nullptr,                kickDriftRadius, &kVerletEstimate },
  { I::EulerCromer,        "Euler-Cromer",        1, false, true,  1,
    false, true,  I::EulerCromer,        nullptr,               nullptr,                kickDriftRadius, nullptr },
  // Newton: gradient, PSD Hessian and line-search energies; then CG on the Hessian.
  { I::ImplicitEuler,      "Implicit Euler",      1, true,  false, 1,
    false, false, I::ImplicitEuler,      "gradient + Hessian",  "block-Jacobi PCG",     backwardEulerRadius, &kFirstOrderEstimate },
  // Local step: the element pass (projections = gradient); global: prefactored solves.
  { I::ProjectiveDynamics, "Projective Dynamics", 1, true,  false, 1,
    false, false, I::ProjectiveDynamics, "local step",          "prefactored Cholesky", backwardEulerRadius, &kFirstOrderEstimate },
  // Newton on the elastic energy alone; order 0: the answer does not depend on the step.
  { I::Static,             "Static",              0, true,  false, 1,
    false, false, I::Static,             "gradient + Hessian",  "block-Jacobi PCG",     staticRadius, nullptr },
  // Implicit Euler's Newton solve of 2h/3 from the extrapolated state.
  { I::Bdf2,               "BDF2",                2, true,  false, 1,
    false, false, I::Bdf2,               "gradient + Hessian",  "block-Jacobi PCG",     bdf2Radius, &kBdf2Estimate },
  // Per-point sweeps: every element evaluated at each of its corners; no linear system.
  { I::VertexBlockDescent, "Vertex Block Descent", 1, true, false, 1,
    false, false, I::VertexBlockDescent, "colored per-point sweeps", "3x3 per point", backwardEulerRadius, &kFirstOrderEstimate },
} };
// clang-format on

constexpr bool tableInEnumOrder()
{
  for (std::size_t i = 0; i < kTable.size(); ++i)
  {
    if (static_cast<std::size_t>(kTable[i].integrator) != i)
    {
      return false;
    }
  }
  return true;
}
static_assert(tableInEnumOrder(), "integrator table rows must follow the enumeration's order");

} // namespace

std::span<const IntegratorFacts> integratorTable()
{
  return kTable;
}

const IntegratorFacts& factsOf(Integrator integrator)
{
  const auto index = static_cast<std::size_t>(integrator);
  if (index >= kTable.size())
  {
    throw std::invalid_argument("factsOf: not an integrator");
  }
  return kTable[index];
}

} // namespace softbody
