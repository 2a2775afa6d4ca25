// The compiled compute kernels of the mass-spring step, one per job (see gpu/shaders).
#pragma once

#include "compute_program.h"

namespace softbody::gpu
{

struct MassSpringKernels
{
  /// Compiles every kernel; throws GpuUnavailableError with the driver's log on failure.
  MassSpringKernels();

  ComputeProgram springForces;
  ComputeProgram volumeForces;
  ComputeProgram gatherAccelerations;
  ComputeProgram tetElasticForces; ///< Corotated or Stable Neo-Hookean tets
  ComputeProgram gatherCornerForces;
  ComputeProgram eulerStep;
  ComputeProgram midpointPredict;
  ComputeProgram midpointStep;
  ComputeProgram kickDrift;
  ComputeProgram strainCorrections;
  ComputeProgram strainApply;
  ComputeProgram holdPoints;
  ComputeProgram floorContacts;
  ComputeProgram divergencePartials;
};

} // namespace softbody::gpu
