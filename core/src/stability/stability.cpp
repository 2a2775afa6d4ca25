#include "softbody/stability/stability.h"

#include <algorithm>
#include <cmath>

namespace softbody
{
namespace
{

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
  return factsOf(integrator).amplificationRadius(h, omega, c);
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
