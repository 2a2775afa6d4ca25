#include "softbody/massspring/stability.h"

#include <algorithm>
#include <cmath>
#include <complex>

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

/// Largest h in [0, 10/omega] with radius <= 1, assuming the stable set is an interval from 0
/// (true for these methods on a damped oscillator). Bisection to ~1e-15 relative.
double stableStepFor(Integrator integrator, double omega, double c)
{
  auto stable = [&](double h) { return amplificationRadius(integrator, h, omega, c) <= 1.0 + 1e-15; };
  double lo = 0.0, hi = 10.0 / omega;
  if (stable(hi))
  {
    return hi;
  }
  for (int iteration = 0; iteration < 80; ++iteration)
  {
    const double mid = 0.5 * (lo + hi);
    (stable(mid) ? lo : hi) = mid;
  }
  return lo;
}

} // namespace

double amplificationRadius(Integrator integrator, double h, double omega, double c)
{
  const double w2 = omega * omega;
  switch (integrator)
  {
    case Integrator::Euler: // x' = x + h v, v' = v + h(-w^2 x - c v)
      return spectralRadius2x2(1.0, h, -h * w2, 1.0 - h * c);
    case Integrator::Verlet: // leapfrog with a constant step is Euler-Cromer on (x, v_{-1/2})
    case Integrator::EulerCromer: // v' = v + h(-w^2 x - c v), x' = x + h v'
      return spectralRadius2x2(1.0 - h * h * w2, h * (1.0 - h * c), -h * w2, 1.0 - h * c);
    case Integrator::ImplicitEuler:
    case Integrator::ProjectiveDynamics: // converged, both solve the backward-Euler equations
    {
      // x' = x + h v', v' = v + h(-w^2 x' - c v'): A = [[1 + hc, h], [-h w^2, 1]] / D.
      const double d = 1.0 + h * c + h * h * w2;
      return spectralRadius2x2((1.0 + h * c) / d, h / d, -h * w2 / d, 1.0 / d);
    }
    case Integrator::Midpoint:
    {
      // A = I + hJ + (hJ)^2 / 2 with J = [[0, 1], [-w^2, -c]], J^2 = [[-w^2, -c], [c w^2, c^2 - w^2]].
      const double h2 = 0.5 * h * h;
      return spectralRadius2x2(1.0 - h2 * w2, h - h2 * c, -h * w2 + h2 * c * w2,
        1.0 - h * c + h2 * (c * c - w2));
    }
  }
  return 0.0;
}

double stableTimeStep(Integrator integrator, double omegaMax, double minDampingTime,
  double maxDampingTime)
{
  if (!(omegaMax > 0.0))
  {
    return 0.0;
  }
  if (integrator == Integrator::Euler && !(minDampingTime > 0.0))
  {
    // Explicit Euler amplifies every undamped oscillation at any step: no stable step exists.
    return 0.0;
  }
  // Stiffness-proportional damping gives each mode c = beta w^2; sweep the modes up to w_max on
  // a geometric grid (the limit of Euler, h <= beta, comes from the low modes; the symplectic
  // limit, h ~ 2 / w, from the top one).
  double best = 10.0 / omegaMax;
  constexpr int kSamples = 48;
  for (double beta : { minDampingTime, maxDampingTime })
  {
    for (int s = 0; s < kSamples; ++s)
    {
      const double omega = omegaMax * std::pow(1e-3, double(s) / (kSamples - 1));
      best = std::min(best, stableStepFor(integrator, omega, beta * omega * omega));
    }
  }
  // Never 0 for a body with stiffness: a tiny step (a stiff material with much damping) is still
  // the stable one; the set-up says when it makes a run impractically long.
  return best;
}

} // namespace softbody
