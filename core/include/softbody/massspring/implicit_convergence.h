// What the implicit integrators report about their solves: the convergence of the last step
// (for the filter's Convergence output, like PBD's) and totals since the simulation began.
#pragma once

#include <vector>

namespace softbody
{

struct ImplicitConvergence
{
  // The last step
  int iterations = 0;        ///< Newton or local/global iterations it ran
  double residual = 0.0;     ///< relative residual at its end (residual / reference)
  bool converged = true;     ///< residual <= tolerance (always true with tolerance 0)
  /// Relative residual before the first iteration and after each one.
  std::vector<double> residualHistory;
  // Totals
  unsigned long long steps = 0;
  unsigned long long unconvergedSteps = 0; ///< steps that ended at maxIterations above tolerance
  unsigned long long iterationsTotal = 0;
  unsigned long long linearIterationsTotal = 0; ///< CG iterations (Implicit Euler)
  unsigned long long lineSearchHalvings = 0;    ///< step shortenings (Implicit Euler)
  /// Steps in which a point moved into its contact plane by more than its elements' size (they
  /// crush or invert the elements there), and the worst of them.
  unsigned long long fastContactSteps = 0;
  double fastestApproach = 0.0;     ///< [m]
  double fastestApproachStep = 0.0; ///< its step [s]
  double fastestApproachSize = 0.0; ///< the element size there [m]
  /// Automatic steps split where a point would reach its contact faster than its elements
  /// (MassSpringSimulation::contactPieces), and the shorter steps they were split into.
  unsigned long long contactSplitSteps = 0;
  unsigned long long contactSplitPieces = 0;
};

} // namespace softbody
