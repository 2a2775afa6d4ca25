// The PBD/XPBD planner: which stages one step runs, decided once from the settings and the
// constraint batches as built.
#pragma once

#include "softbody/common/step_plan.h"
#include "softbody/pbd/pbd_constraints.h"
#include "softbody/pbd/pbd_settings.h"

namespace softbody
{

/// predict; per iteration the solve stage of each constraint type that can move a particle
/// (present and of nonzero stiffness: PBD stiffness > 0, XPBD compliance finite) and the floor
/// when there is one; the residual when a tolerance is set or convergence is reported; the
/// velocity update; floor friction/restitution only when either is nonzero; link plasticity
/// and breaking only when links can break or flow; the divergence check.
StepPlan planPbd(const PbdSettings& settings, const DistanceBatch& links,
  const VolumeBatch& volumes, const AttachmentBatch& attachments);

/// "Gauss-Seidel", "SOR", "Jacobi" or "parallel Gauss-Seidel".
const char* pbdSolverName(PbdSolver solver, double relaxation);

} // namespace softbody
