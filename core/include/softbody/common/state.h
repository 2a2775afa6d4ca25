// The state that evolves during a simulation, apart from the settings that do not: what the
// frame cache snapshots and what a stepper restores to resume.
#pragma once

#include "softbody/common/geometry.h"

#include <vector>

namespace softbody
{

/// The dynamic state; a copy of it is a complete snapshot (the frame cache stores these).
struct DynamicState
{
  std::vector<Vec3> positions;  ///< [m]
  /// [m/s]. For Verlet this is the staggered velocity v(t - h/2) of position Verlet, i.e.
  /// (x(t) - x(t-h)) / h: Stoermer-Verlet x+ = 2x - x- + h^2 a is exactly the leapfrog
  /// v(t+h/2) = v(t-h/2) + h a(t), x(t+h) = x(t) + h v(t+h/2), which needs no x- array and
  /// lets the step size change between frames.
  std::vector<Vec3> velocities;
  double time = 0.0;            ///< simulated time [s]
  unsigned long long stepCount = 0;
  /// Size of the previous step [s] (0 before the first). Verlet's kick spans the half steps on
  /// both sides, (h_prev + h) / 2, so its first step is the half kick that starts leapfrog
  /// exactly: free fall is reproduced to rounding.
  double previousStep = 0.0;
  /// History of multistep integrators (BDF2): the positions and velocities before the last
  /// step, previousStep before these. Empty until the first step, and for the others.
  std::vector<Vec3> previousPositions;
  std::vector<Vec3> previousVelocities;
  /// History of Verlet's embedded error estimate (integrators/local_error.h), kept under
  /// error-controlled steps only: the acceleration of the last step's kick [m/s^2].
  std::vector<Vec3> previousAccelerations;
  /// Error-controlled steps: the step the controller proposes next [s] (0: none yet).
  double proposedStep = 0.0;
  /// History of models whose links change as they move (PBD plastic and breakable links):
  /// the current rest length and broken flag of each link. Empty for models without any.
  std::vector<double> linkRestLengths;
  std::vector<unsigned char> linkBroken;
  /// PBD/XPBD restitution of whole bodies: per point, the normal approach speed [m/s] its body
  /// hit an obstacle (the floor included) with while that bounce is unresolved (0 = none;
  /// negative: the body has been at rest on it for one substep), and the unit normal it hit
  /// along. Empty without restitution.
  std::vector<double> impactSpeeds;
  std::vector<Vec3> impactNormals;
  /// PBD, and XPBD with a rigid constraint type, where no force is a function of the state:
  /// per point, the force the projections of the last substep gave it, the multipliers'
  /// sum_c lambda_c dC_c/dx / h^2 [N], from which the supports' reactions are read. Empty where
  /// nothing is held or the reactions come from the state.
  std::vector<Vec3> supportForces;
};

} // namespace softbody
