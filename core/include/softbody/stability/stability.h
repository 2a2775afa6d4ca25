// Estimates of the largest stable time step of each explicit integrator.
//
// The highest natural angular frequency w_max of the linearized system M^-1 K at rest comes from
// highest_frequency.h (a Lanczos upper estimate, capped by a Gershgorin bound). Each integrator
// is then applied to the damped test oscillator x'' = -w^2 x - c x', c = beta w^2
// (stiffness-proportional damping): the largest h for which the spectral radius of its 2x2
// amplification matrix stays <= 1, over a sweep of frequencies up to w_max, is its stability
// limit. Explicit Euler is unstable for any h without damping; it
// is stable for h <= beta (under-damped modes) and h <= ~2 / (beta w^2) (over-damped ones).
#pragma once

#include "softbody/integrators/integrator.h"
#include "softbody/stability/highest_frequency.h"
#include "softbody/material/material.h"

#include <vector>

namespace softbody
{

/// Spectral radius of one step of `integrator` on x'' = -omega^2 x - c x'.
double amplificationRadius(Integrator integrator, double h, double omega, double c);

/// Largest stable step [s] for frequencies up to omegaMax with damping c = beta w^2, taking the
/// worse of the two damping times given (elements may differ). 0 when no step is stable
/// (explicit Euler without damping).
double stableTimeStep(Integrator integrator, double omegaMax, double minDampingTime,
  double maxDampingTime);

} // namespace softbody
