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
  : Topo(topology)
  , Constants(*elements.network)
  , Tets(isContinuum(elements.model) ? elements.tets : nullptr)
  , InverseMass(masses.inverseMass)
  , Potential(makeIncrementalPotential(topology, elements, masses, scene.gravity))
  , Solver(*Potential, scene, ImplicitStepSolver::LineSearch::Armijo)
  , History(scene.implicit.projectiveHistory)
{
  FreeIndex.assign(topology.vertexCount, -1);
  for (std::size_t i = 0; i < topology.vertexCount; ++i)
  {
    if (InverseMass[i] > 0.0)
    {
      FreeIndex[i] = static_cast<std::int32_t>(FreeVertex.size());
      FreeVertex.push_back(static_cast<std::int32_t>(i));
    }
  }
  if (Constants.hasVolumeTerm)
  {
    TetWeight.resize(topology.tets.size());
    for (std::size_t t = 0; t < topology.tets.size(); ++t)
    {
      const Tet& tet = topology.tets[t];
      const auto g = tetVolumeGradients(restPositions[tet[0]], restPositions[tet[1]],
        restPositions[tet[2]], restPositions[tet[3]]);
      TetWeight[t] = g[0].squaredNorm() + g[1].squaredNorm() + g[2].squaredNorm() +
        g[3].squaredNorm();
    }
  }
}

void ProjectiveDynamicsStepper::factor(double h)
{
  const auto start = std::chrono::steady_clock::now();
  using Triplet = Eigen::Triplet<double>;
  std::vector<Triplet> entries;
  entries.reserve(FreeVertex.size() + 4 * Topo.edges.size() + 16 * TetWeight.size());
  for (std::size_t r = 0; r < FreeVertex.size(); ++r)
  {
    const int row = static_cast<int>(r);
    entries.emplace_back(row, row, 1.0 / (h * h * InverseMass[FreeVertex[r]]));
  }
  // Entries that couple to a fixed point stay on the free point's diagonal only: the fixed one
  // does not move, so A_ff is the matrix of the free unknowns.
  const auto addPair = [&](std::int32_t i, std::int32_t j, double weight) {
    const int fi = FreeIndex[i], fj = FreeIndex[j];
    if (fi >= 0 && fj >= 0)
    {
      entries.emplace_back(fi, fj, weight);
    }
  };
  for (std::size_t e = 0; e < Topo.edges.size(); ++e)
  {
    const double w = Constants.springStiffness[e] + Constants.springDamping[e] / h;
    const Edge& edge = Topo.edges[e];
    addPair(edge.a, edge.a, w);
    addPair(edge.b, edge.b, w);
    addPair(edge.a, edge.b, -w);
    addPair(edge.b, edge.a, -w);
  }
  for (std::size_t t = 0; t < TetWeight.size(); ++t)
  {
    const double w =
      (Constants.volumeStiffness[t] + Constants.volumeDamping[t] / h) * TetWeight[t];
    const Tet& tet = Topo.tets[t];
    for (int a = 0; a < 4; ++a)
    {
      for (int b = 0; b < 4; ++b)
      {
        addPair(tet[a], tet[b], w * ((a == b ? 1.0 : 0.0) - 0.25));
      }
    }
  }
  for (std::size_t t = 0; Tets && t < Topo.tets.size(); ++t)
  {
    const LameParameters& p = Tets->linear[t];
    const double viscosity = Tets->damped ? Tets->dampingTime[t] / h : 0.0;
    const double w = (2.0 * p.mu + p.lambda) * Tets->restVolume[t] * (1.0 + viscosity);
    const std::array<Vec3, 4>& g = Tets->shapeGradients[t];
    const Tet& tet = Topo.tets[t];
    for (int a = 0; a < 4; ++a)
    {
      for (int b = 0; b < 4; ++b)
      {
        addPair(tet[a], tet[b], w * g[static_cast<std::size_t>(a)].dot(g[static_cast<std::size_t>(b)]));
      }
    }
  }
  Eigen::SparseMatrix<double> matrix(
    static_cast<Eigen::Index>(FreeVertex.size()), static_cast<Eigen::Index>(FreeVertex.size()));
  matrix.setFromTriplets(entries.begin(), entries.end());
  Cholesky.compute(matrix);
  if (Cholesky.info() != Eigen::Success)
  {
    // A is M / h^2 plus positive semi-definite terms: this means a non-finite constant.
    throw std::runtime_error("Projective Dynamics: the global matrix could not be factored "
                             "(not positive definite); check the material constants.");
  }
  FactoredStep = h;
  FactorNonZeros = static_cast<std::size_t>(Cholesky.matrixL().nestedExpression().nonZeros());
  FactorSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ++Factorizations;
}

void ProjectiveDynamicsStepper::solve(
  const std::vector<Vec3>& q, const MotionFilter& filter, std::vector<Vec3>& direction)
{
  // x, y and z share A: three independent solves, one task each (Eigen's sparse triangular
  // solve takes a many-column right-hand side one column at a time anyway).
  const auto rows = static_cast<Eigen::Index>(FreeVertex.size());
  Rhs.resize(rows, 3);
  parallelFor(FreeVertex.size(), 4096, [&](std::size_t r) {
    Rhs.row(static_cast<Eigen::Index>(r)) = -filter.apply(FreeVertex[r], q[FreeVertex[r]]).transpose();
  });
  Solution.resize(rows, 3);
  parallelFor(3, 1, [&](std::size_t axis) {
    const auto a = static_cast<Eigen::Index>(axis);
    Solution.col(a) = Cholesky.solve(Rhs.col(a));
  });
  direction.assign(q.size(), Vec3::Zero());
  parallelFor(FreeVertex.size(), 4096, [&](std::size_t r) {
    const std::size_t i = static_cast<std::size_t>(FreeVertex[r]);
    direction[i] = filter.apply(i, Solution.row(static_cast<Eigen::Index>(r)).transpose());
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
