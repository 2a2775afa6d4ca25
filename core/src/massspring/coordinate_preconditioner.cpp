#include "softbody/massspring/coordinate_preconditioner.h"

#include "softbody/common/parallel.h"

#include <Eigen/IterativeLinearSolvers>

#include <chrono>
#include <cmath>

namespace softbody
{

struct CoordinatePreconditioner::IncompleteFactor
{
  Eigen::IncompleteCholesky<double, Eigen::Lower, Eigen::AMDOrdering<int>> factor;
  bool factored = false;
  Eigen::VectorXd column; ///< one coordinate's solution, reused across applications
};

CoordinatePreconditioner::CoordinatePreconditioner(const Topology& topology,
  const BodyElements& elements, const PointMasses& masses,
  const std::vector<Vec3>& restPositions, CholeskyBackend backend, bool incomplete)
  : Matrix(topology, elements, masses, restPositions)
  , Cholesky(backend)
  , Incomplete(incomplete ? std::make_unique<IncompleteFactor>() : nullptr)
{
}

CoordinatePreconditioner::~CoordinatePreconditioner() = default;

std::size_t CoordinatePreconditioner::factorBytes() const
{
  if (!Incomplete)
  {
    return Cholesky.factorBytes();
  }
  if (!Incomplete->factored)
  {
    return 0;
  }
  // L's values and row indices, its column starts, the scaling and the two permutations.
  const auto& l = Incomplete->factor.matrixL();
  const std::size_t n = static_cast<std::size_t>(l.cols());
  return static_cast<std::size_t>(l.nonZeros()) * (sizeof(double) + sizeof(int)) +
    (n + 1) * sizeof(int) + n * (sizeof(double) + 2 * sizeof(int));
}

std::string CoordinatePreconditioner::prepare(double h, bool inertia, const std::vector<char>& active)
{
  const std::vector<std::int32_t>& rows = Matrix.freeVertices();
  Held.resize(rows.size());
  parallelFor(rows.size(), 4096, [&](std::size_t r) {
    Held[r] = active[static_cast<std::size_t>(rows[r])] ? 0 : 1;
  });
  const bool stepFits = inertia == FactoredInertia &&
    ((std::isinf(h) && std::isinf(FactoredStep)) ||
      (h <= kStepRatio * FactoredStep && FactoredStep <= kStepRatio * h));
  const bool factored = Incomplete ? Incomplete->factored : Cholesky.factored();
  if (factored && stepFits && Held == FactoredHeld)
  {
    return {};
  }
  const auto start = std::chrono::steady_clock::now();
  Eigen::SparseMatrix<double> a = Matrix.assemble(h, inertia);
  // A held point does not move: its row and column become the identity's, so the free points
  // are preconditioned by A_ff (the held points act as supports, as they do in H).
  for (Eigen::Index column = 0; column < a.outerSize(); ++column)
  {
    for (Eigen::SparseMatrix<double>::InnerIterator entry(a, column); entry; ++entry)
    {
      if (Held[static_cast<std::size_t>(entry.row())] || Held[static_cast<std::size_t>(column)])
      {
        entry.valueRef() = entry.row() == column ? 1.0 : 0.0;
      }
    }
  }
  std::string failure;
  if (Incomplete)
  {
    // Eigen shifts the scaled diagonal until the incomplete factor exists, so it fails only on
    // a matrix it cannot scale (a zero or negative diagonal).
    Incomplete->factor.compute(a);
    Incomplete->factored = Incomplete->factor.info() == Eigen::Success;
    if (!Incomplete->factored)
    {
      failure = "the incomplete Cholesky factorization reported a numerical issue";
    }
  }
  else
  {
    failure = Cholesky.factor(a);
  }
  FactorSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ++Factorizations;
  if (!failure.empty())
  {
    FactoredHeld.clear();
    return failure;
  }
  FactoredStep = h;
  FactoredInertia = inertia;
  FactoredHeld = Held;
  return {};
}

void CoordinatePreconditioner::apply(const std::vector<Vec3>& r, std::vector<Vec3>& z)
{
  const std::vector<std::int32_t>& rows = Matrix.freeVertices();
  Columns.resize(static_cast<Eigen::Index>(rows.size()), 3);
  parallelFor(rows.size(), 4096, [&](std::size_t k) {
    Columns.row(static_cast<Eigen::Index>(k)) = r[static_cast<std::size_t>(rows[k])].transpose();
  });
  if (Incomplete)
  {
    // Eigen's incomplete factor solves one right-hand side at a time; each goes through a
    // kept column so that no CG iteration allocates.
    for (Eigen::Index c = 0; c < 3; ++c)
    {
      Incomplete->column = Incomplete->factor.solve(Columns.col(c));
      Columns.col(c) = Incomplete->column;
    }
  }
  else
  {
    Cholesky.solve(Columns);
  }
  z = r; // fixed points (no row): the filter zeroes them
  parallelFor(rows.size(), 4096, [&](std::size_t k) {
    z[static_cast<std::size_t>(rows[k])] = Columns.row(static_cast<Eigen::Index>(k)).transpose();
  });
}

} // namespace softbody
