/**
 * @class   vtkSoftBodyImplicitReport
 * @brief   The implicit integrators' convergence in the Soft Body filter's outputs.
 *
 * Implicit Euler and Projective Dynamics report like PBD does: field data "Iterations" and
 * "Residual" (the frame's last step, relative to the reference acceleration), plus
 * "UnconvergedSteps" and "LinearIterations" (totals), and the Convergence table (residual
 * before the first iteration and after each, "Iteration" from 0). Steps that end above the
 * tolerance become a warning with the remedy.
 */
#ifndef vtkSoftBodyImplicitReport_h
#define vtkSoftBodyImplicitReport_h

#include "softbody/massspring/implicit_convergence.h"

#include <string>

class vtkFieldData;
class vtkTable;
namespace softbody
{
class Simulation;
}

struct vtkSoftBodyImplicitReport
{
  static void AddFields(const softbody::ImplicitConvergence& convergence, vtkFieldData* field);
  static void FillTable(const softbody::ImplicitConvergence& convergence, vtkTable* output);
  /// Empty when every step converged; else how many did not, the residual, and what to do.
  static std::string Warning(const softbody::ImplicitConvergence& convergence,
    const char* integrator, int maxIterations);
  /// Empty unless some step moved a point into its contact plane by more than its elements'
  /// size; else how many, the worst approach, and the TimeStep that avoids it.
  static std::string ContactWarning(const softbody::ImplicitConvergence& convergence,
    const char* integrator);
  /// Said before the run: empty unless `simulation` is a Mass-Spring body under an implicit
  /// integrator that steps of `step` [s] will land on the floor faster than its elements take
  /// in one step (MassSpringSimulation::landingStepWarning).
  static std::string LandingWarning(const softbody::Simulation& simulation, double step);
};

#endif
