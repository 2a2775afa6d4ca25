#include "softbody/massspring/implicit_euler.h"

#include "softbody/common/parallel.h"
#include "softbody/common/stepping.h"

#include <algorithm>

namespace softbody
{
namespace
{

constexpr double kMaxForcing = 0.1; // CG's relative accuracy in the first Newton iterations

} // namespace

ImplicitEulerStepper::ImplicitEulerStepper(const Topology& topology,
  const BodyElements& elements, const PointMasses& masses, const SceneSettings& scene,
  bool equilibrium)
  : Potential(makeIncrementalPotential(topology, elements, masses, scene.gravity))
  , Solver(*Potential, scene, ImplicitStepSolver::LineSearch::Armijo)
  , Hessian(topology)
{
  if (equilibrium)
  {
    Potential->makeStatic();
  }
}

void ImplicitEulerStepper::step(double h, DynamicState& state, StepPlan& plan)
{
  const auto newtonDirection = [&](const ImplicitStepSolver::Iterate& at,
                                 std::vector<Vec3>& direction) {
    const double residual = at.relativeResidual, goal = at.relativeGoal;
    {
      ScopedStageTimer timer(at.plan, Stage::Forces);
      Potential->assembleHessian(at.x, Hessian);
    }
    ScopedStageTimer timer(at.plan, Stage::LinearSolve);
    // Solve only as well as this iteration can use: loosely far from the solution, tightly
    // near it (eta ~ r keeps Newton quadratic), never much below what the tolerance needs.
    const double forcing = std::min(kMaxForcing, std::max(residual, 0.5 * goal / residual));
    Rhs.resize(at.gradient.size());
    parallelFor(at.gradient.size(), 4096, [&](std::size_t i) { Rhs[i] = -at.gradient[i]; });
    return solveBlockPcg(Hessian, at.filter, Rhs, forcing, kMaxLinearIterations, direction, LinearWork)
      .iterations;
  };
  Solver.step(h, state, plan, newtonDirection, Convergence);
}

} // namespace softbody
