#include "mass_spring_kernels.h"

#include "softbody_gpu_shaders.h"

namespace softbody::gpu
{

MassSpringKernels::MassSpringKernels()
  : springForces("spring_forces", shaders::kSpringForcesSource)
  , volumeForces("volume_forces", shaders::kVolumeForcesSource)
  , gatherAccelerations("gather_accelerations", shaders::kGatherAccelerationsSource)
  , tetElasticForces("tet_elastic_forces", shaders::kTetElasticForcesSource)
  , gatherCornerForces("gather_corner_forces", shaders::kGatherCornerForcesSource)
  , eulerStep("euler_step", shaders::kEulerStepSource)
  , midpointPredict("midpoint_predict", shaders::kMidpointPredictSource)
  , midpointStep("midpoint_step", shaders::kMidpointStepSource)
  , kickDrift("kick_drift", shaders::kKickDriftSource)
  , strainCorrections("strain_corrections", shaders::kStrainCorrectionsSource)
  , strainApply("strain_apply", shaders::kStrainApplySource)
  , holdPoints("hold_points", shaders::kHoldPointsSource)
  , floorContacts("floor_contacts", shaders::kFloorContactsSource)
  , divergencePartials("divergence_partials", shaders::kDivergencePartialsSource)
{
}

} // namespace softbody::gpu
