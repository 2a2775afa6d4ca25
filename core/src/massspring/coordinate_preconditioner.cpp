#include "softbody/massspring/coordinate_preconditioner.h"

#include "softbody/common/parallel.h"

#include <chrono>
#include <cmath>

namespace softbody
{

CoordinatePreconditioner::CoordinatePreconditioner(const Topology& topology,
  const BodyElements& elements, const PointMasses& masses,
  const std::vector<Vec3>& restPositions, LinearPreconditioner kind, CholeskyBackend backend)
  : Matrix(topology, elements, masses, restPositions)
  , Kind(kind)
  , Solver(makeCoordinateSolver(kind, backend))
{
}

CoordinatePreconditioner::~CoordinatePreconditioner() = default;

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
  if (Solver->factored() && stepFits && Held == FactoredHeld)
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
  const std::string failure = Solver->factor(a);
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
  Solver->solve(Columns);
  z = r; // fixed points (no row): the filter zeroes them
  parallelFor(rows.size(), 4096, [&](std::size_t k) {
    z[static_cast<std::size_t>(rows[k])] = Columns.row(static_cast<Eigen::Index>(k)).transpose();
  });
}

} // namespace softbody
