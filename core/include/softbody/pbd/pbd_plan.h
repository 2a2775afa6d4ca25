// The PBD/XPBD planner: which stages one step runs, decided once from the settings and the
// constraint batches as built.
#pragma once

#include "softbody/common/step_plan.h"
#include "softbody/pbd/pbd_constraints.h"
#include "softbody/pbd/pbd_settings.h"

namespace softbody
{

/// predict; collision detection once per substep when `collisions` (something to collide
/// with: the floor, obstacles, other bodies or the body itself, and the mode not Off); per
/// iteration the solve stage of each constraint type that can move a particle (present and of
/// nonzero stiffness; a continuum body's tets always),
/// nonzero stiffness: PBD stiffness > 0, XPBD compliance finite), then the contacts (with
/// their friction); the residual when a tolerance is set or convergence is reported; the
/// velocity update; restitution only when it is nonzero; link plasticity and breaking only
/// when links can break or flow; the divergence check.
StepPlan planPbd(const PbdSettings& settings, const DistanceBatch& links,
  const TetElasticBatch& tetElasticity, const VolumeBatch& volumes,
  const AttachmentBatch& attachments, bool collisions = false);

/// "Gauss-Seidel", "SOR", "Jacobi" or "parallel Gauss-Seidel".
const char* pbdSolverName(PbdSolver solver, double relaxation);

} // namespace softbody
