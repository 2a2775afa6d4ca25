#include "softbody/massspring/implicit_euler.h"

#include "softbody/common/parallel.h"
#include "softbody/common/stepping.h"

#include <algorithm>
#include <limits>

namespace softbody
{
namespace
{

constexpr double kMaxForcing = 0.1; // CG's relative accuracy in the first Newton iterations
/// Below this residual (relative to the step's start) Newton tries the exact Hessian.
constexpr double kExactHessianBelow = 1e-2;

} // namespace

ImplicitEulerStepper::ImplicitEulerStepper(const Topology& topology,
  const BodyElements& elements, const PointMasses& masses,
  const std::vector<Vec3>& restPositions, const SceneSettings& scene, bool equilibrium)
  : Potential(makeIncrementalPotential(topology, elements, masses, scene.gravity))
  , Solver(*Potential, scene, ImplicitStepSolver::LineSearch::Armijo)
  , Hessian(topology)
  , Equilibrium(equilibrium)
{
  if (scene.implicit.preconditioner != LinearPreconditioner::BlockJacobi)
  {
    Coordinate = std::make_unique<CoordinatePreconditioner>(topology, elements, masses, restPositions,
      scene.implicit.preconditioner, scene.implicit.cholesky);
  }
  if (equilibrium)
  {
    Potential->makeStatic();
  }
}

PcgPreconditioner* ImplicitEulerStepper::preconditioner(double h)
{
  if (!Coordinate)
  {
    return nullptr;
  }
  // The static solve's matrix has neither inertia nor damping (h = infinity).
  const std::string failure = Equilibrium
    ? Coordinate->prepare(std::numeric_limits<double>::infinity(), false, Potential->active())
    : Coordinate->prepare(h, true, Potential->active());
  if (failure.empty())
  {
    return Coordinate.get();
  }
  PreconditionerWarning = std::string("the ") +
    (Coordinate->kind() == LinearPreconditioner::AlgebraicMultigrid ? "algebraic multigrid" : "coordinate") +
    " preconditioner could not be made (" + failure + "); the implicit solve uses block Jacobi instead";
  Coordinate.reset();
  return nullptr;
}

void ImplicitEulerStepper::step(double h, DynamicState& state, StepPlan& plan)
{
  const auto newtonDirection = [&](const ImplicitStepSolver::Iterate& at,
                                 std::vector<Vec3>& direction) {
    const double residual = at.relativeResidual, goal = at.relativeGoal;
    // Solve only as well as this iteration can use: loosely far from the solution, tightly
    // near it (eta ~ r keeps Newton quadratic), never much below what the tolerance needs.
    const double forcing = std::min(kMaxForcing, std::max(residual, 0.5 * goal / residual));
    Rhs.resize(at.gradient.size());
    parallelFor(at.gradient.size(), 4096, [&](std::size_t i) { Rhs[i] = -at.gradient[i]; });
    // Near the solution the exact Hessian, where the model has one: the PSD projection clamps
    // the slightly negative eigenvalues of every slightly compressed tet (both continuum laws'
    // twist modes are 0 at rest), and that error alone keeps Newton from converging
    // quadratically. Where the exact system is not positive definite along CG's path, or its
    // direction does not descend, the projected one is solved instead.
    bool exact = residual < kExactHessianBelow && Potential->hasExactHessian();
    int iterations = 0;
    for (;;)
    {
      {
        ScopedStageTimer timer(at.plan, Stage::Forces);
        Potential->assembleHessian(at.x, Hessian, exact);
      }
      ScopedStageTimer timer(at.plan, Stage::LinearSolve);
      const PcgResult solved = solveBlockPcg(Hessian, at.filter, Rhs, forcing, kMaxLinearIterations,
        direction, LinearWork, preconditioner(h));
      iterations += solved.iterations;
      if (!exact)
      {
        return iterations;
      }
      const double slope = parallelSum(direction.size(),
        [&](std::size_t i) { return direction[i].dot(at.gradient[i]); });
      if (!solved.indefinite && slope < 0.0)
      {
        ++ExactHessianSteps;
        return iterations;
      }
      exact = false;
      ++ExactHessianFallbacks;
    }
  };
  Solver.step(h, state, plan, newtonDirection, Convergence);
}

} // namespace softbody
