#include "softbody/massspring/vertex_block_descent.h"

#include "softbody/common/parallel.h"
#include "softbody/common/stepping.h"

#include <Eigen/Cholesky>

namespace softbody
{

VertexBlockDescentStepper::VertexBlockDescentStepper(const Topology& topology, const BodyElements& elements,
  const PointMasses& masses, const SceneSettings& scene)
  : Potential(makeIncrementalPotential(topology, elements, masses, scene.gravity))
  // Any decrease: a sweep is not a Newton step, so Armijo's model of the decrease does not apply.
  , Solver(*Potential, scene, ImplicitStepSolver::LineSearch::Decrease)
  , Colors(colorVertices(topology))
  , Rho(scene.implicit.chebyshevRadius)
{
}

void VertexBlockDescentStepper::sweep(const ImplicitStepSolver::Iterate& at, std::vector<Vec3>& direction)
{
  ScopedStageTimer timer(at.plan, Stage::Forces);
  Potential->beginVertexBlocks();
  Y = at.x;
  const MotionFilter& filter = at.filter;
  for (std::size_t color = 0; color < Colors.colorCount(); ++color)
  {
    const auto begin = static_cast<std::size_t>(Colors.colorOffsets[color]);
    const auto end = static_cast<std::size_t>(Colors.colorOffsets[color + 1]);
    parallelFor(end - begin, 64, [&](std::size_t k) {
      const auto i = static_cast<std::size_t>(Colors.order[begin + k]);
      if (!Potential->active()[i] || !filter.moves(i))
      {
        return;
      }
      Vec3 gradient;
      Mat3 hessian;
      Potential->vertexBlock(i, Y, at.x, gradient, hessian);
      // The step restricted to the directions the point may move in: with S the filter's
      // matrix, (S^T H S + I - S^T S) z = -S^T g and the move S z (S = I for a free point).
      Mat3 s;
      for (int axis = 0; axis < 3; ++axis)
      {
        s.col(axis) = filter.apply(i, Vec3::Unit(axis));
      }
      const Mat3 reduced = s.transpose() * hessian * s + Mat3::Identity() - s.transpose() * s;
      const Eigen::LLT<Mat3> factor(reduced);
      if (factor.info() != Eigen::Success)
      {
        return; // no curvature to step on (a static point without elements): left where it is
      }
      Y[i] += s * factor.solve(-(s.transpose() * gradient));
    });
  }
  direction.resize(Y.size());
  parallelFor(Y.size(), 4096, [&](std::size_t i) { direction[i] = Y[i] - at.x[i]; });
}

void VertexBlockDescentStepper::accelerate(const ImplicitStepSolver::Iterate& at, std::vector<Vec3>& direction)
{
  if (at.restart || Current.size() != at.x.size())
  {
    Omega = 1.0; // the first sweep of a step is taken as it is
    Previous = at.x;
    Current = at.x;
    return;
  }
  if (at.x != Current) // else the same iteration asked again: the same omega and previous iterate
  {
    Previous.swap(Current);
    Current = at.x;
    Omega = Omega == 1.0 ? 2.0 / (2.0 - Rho * Rho) : 4.0 / (4.0 - Rho * Rho * Omega);
  }
  parallelFor(at.x.size(), 4096, [&](std::size_t i) {
    const Vec3 accelerated = Omega * (at.x[i] + direction[i] - Previous[i]) + Previous[i];
    direction[i] = at.filter.apply(i, accelerated - at.x[i]);
  });
}

void VertexBlockDescentStepper::step(double h, DynamicState& state, StepPlan& plan)
{
  const auto sweepDirection = [&](const ImplicitStepSolver::Iterate& at, std::vector<Vec3>& direction) {
    sweep(at, direction);
    if (Rho > 0.0)
    {
      accelerate(at, direction);
    }
    return 0;
  };
  Solver.step(h, state, plan, sweepDirection, Convergence);
}

} // namespace softbody
