#include "softbody/massspring/projective_dynamics.h"
#include "softbody/massspring/model_potential_factory.h"

#include "softbody/common/errors.h"
#include "softbody/common/parallel.h"
#include "softbody/common/stepping.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace softbody
{
ProjectiveDynamicsStepper::ProjectiveDynamicsStepper(const Topology& topology,
  const BodyElements& elements, const PointMasses& masses,
  const std::vector<Vec3>& restPositions, const SceneSettings& scene)
  : Matrix(topology, elements, masses, restPositions)
  , Cholesky(scene.implicit.cholesky)
  , Potential(makeIncrementalPotential(topology, elements, masses, scene.gravity))
  , Solver(*Potential, scene, ImplicitStepSolver::LineSearch::Armijo)
  , History(scene.implicit.projectiveHistory)
{
}

void ProjectiveDynamicsStepper::factor(double h)
{
  const auto start = std::chrono::steady_clock::now();
  const std::string failure = Cholesky.factor(Matrix.assemble(h));
  if (!failure.empty())
  {
    // A is M / h^2 plus positive semi-definite terms: this means a non-finite constant.
    throw std::runtime_error("Projective Dynamics: the global matrix could not be factored (" +
      failure + "); check the material constants.");
  }
  FactoredStep = h;
  FactorNonZeros = Cholesky.factorNonZeros();
  FactorBytes = Cholesky.factorBytes();
  FactorSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ++Factorizations;
}

void ProjectiveDynamicsStepper::solve(
  const std::vector<Vec3>& q, const MotionFilter& filter, std::vector<Vec3>& direction)
{
  // x, y and z share A: one solve with three right-hand sides, one pass over the factor.
  const std::vector<std::int32_t>& rows = Matrix.freeVertices();
  Rhs.resize(static_cast<Eigen::Index>(rows.size()), 3);
  parallelFor(rows.size(), 4096, [&](std::size_t r) {
    Rhs.row(static_cast<Eigen::Index>(r)) = -filter.apply(rows[r], q[rows[r]]).transpose();
  });
  Cholesky.solve(Rhs);
  direction.assign(q.size(), Vec3::Zero());
  parallelFor(rows.size(), 4096, [&](std::size_t r) {
    const std::size_t i = static_cast<std::size_t>(rows[r]);
    direction[i] = filter.apply(i, Rhs.row(static_cast<Eigen::Index>(r)).transpose());
  });
}

void ProjectiveDynamicsStepper::step(double h, DynamicState& state, StepPlan& plan)
{
  if (h != FactoredStep)
  {
    ScopedStageTimer timer(plan, Stage::LinearSolve);
    factor(h);
  }
  const auto globalSolve = [&](const ImplicitStepSolver::Iterate& at,
                             std::vector<Vec3>& result) {
    ScopedStageTimer timer(at.plan, Stage::LinearSolve);
    direction(at, result);
    return 0;
  };
  Solver.step(h, state, plan, globalSolve, Convergence);
}

namespace
{
double dot(const std::vector<Vec3>& a, const std::vector<Vec3>& b)
{
  return parallelSum(a.size(), [&](std::size_t i) { return a[i].dot(b[i]); });
}
} // namespace

void ProjectiveDynamicsStepper::direction(
  const ImplicitStepSolver::Iterate& at, std::vector<Vec3>& result)
{
  const std::size_t n = at.x.size();
  Q.resize(n);
  parallelFor(n, 4096, [&](std::size_t i) { Q[i] = at.filter.apply(i, at.gradient[i]); });
  if (History == 0)
  {
    solve(Q, at.filter, result);
    return;
  }
  if (at.restart)
  {
    Pairs.clear();
  }
  else
  {
    Pair pair;
    pair.s.resize(n);
    pair.y.resize(n);
    parallelFor(n, 4096, [&](std::size_t i) {
      pair.s[i] = at.x[i] - LastX[i];
      pair.y[i] = Q[i] - LastGradient[i];
    });
    const double ys = dot(pair.y, pair.s);
    // Keep only pairs with positive curvature: the L-BFGS matrix stays positive definite.
    if (ys > 1e-12 * std::sqrt(dot(pair.y, pair.y) * dot(pair.s, pair.s)))
    {
      pair.rho = 1.0 / ys;
      if (static_cast<int>(Pairs.size()) == History)
      {
        Pairs.erase(Pairs.begin());
      }
      Pairs.push_back(std::move(pair));
    }
  }
  LastX = at.x;
  LastGradient = Q;

  // Two-loop recursion on q = S grad Phi, with A^-1 in the middle.
  Alpha.resize(Pairs.size());
  for (std::size_t k = Pairs.size(); k-- > 0;)
  {
    Alpha[k] = Pairs[k].rho * dot(Pairs[k].s, Q);
    const double a = Alpha[k];
    parallelFor(n, 4096, [&](std::size_t i) { Q[i] -= a * Pairs[k].y[i]; });
  }
  solve(Q, at.filter, result); // result = -A^-1 q
  for (std::size_t k = 0; k < Pairs.size(); ++k)
  {
    // In the negated variable r = -result: r += s (alpha - rho y . r).
    const double beta = -Pairs[k].rho * dot(Pairs[k].y, result);
    const double a = Alpha[k];
    parallelFor(n, 4096, [&](std::size_t i) { result[i] -= (a - beta) * Pairs[k].s[i]; });
  }
  // Pairs from before a contact change may leave the filtered space: filter the result. It
  // stays a descent direction: g . S H q = q . H q > 0 for the positive definite L-BFGS H.
  parallelFor(n, 4096, [&](std::size_t i) { result[i] = at.filter.apply(i, result[i]); });
}

} // namespace softbody
