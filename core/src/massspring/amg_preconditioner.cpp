#include "softbody/massspring/amg_preconditioner.h"

#include "softbody/common/errors.h"

#if SOFTBODY_HAVE_HYPRE
#include <HYPRE.h>
#include <HYPRE_parcsr_ls.h>
#include <_hypre_parcsr_ls.h> // the hierarchy's levels and vector data: bytes(), solve()
#include <mpi.h>

#include <cstdlib>
#include <cstring>
#include <mutex>
#include <vector>
#endif

namespace softbody
{

#if SOFTBODY_HAVE_HYPRE

namespace
{

/// hypre keeps process-wide state (its error flag, its memory handle), and Debian's hypre is
/// built on MPI: every call into it holds this lock, so that simulations stepped on different
/// threads never call it at once. That is also what MPI_THREAD_SERIALIZED asks of MPI.
std::mutex& hypreLock()
{
  static std::mutex lock;
  return lock;
}

/// Starts MPI (where the host has not: a plain program, the ParaView GUI) and hypre, once per
/// process. Returns why it failed, or an empty string. MPI is finalized at exit only if it was
/// started here: a host that started it (pvbatch) finalizes it itself. hypre's own handle is
/// left to the end of the process rather than finalized, because a hierarchy destroyed after
/// HYPRE_Finalize (one held in static storage) would still use it.
const std::string& startHypre()
{
  static const std::string failure = []() -> std::string {
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (!initialized)
    {
      int provided = 0;
      if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided) != MPI_SUCCESS)
      {
        return "MPI_Init_thread failed";
      }
      std::atexit([] {
        int finalized = 0;
        MPI_Finalized(&finalized);
        if (!finalized)
        {
          MPI_Finalize();
        }
      });
    }
    if (HYPRE_Init() != 0)
    {
      return "HYPRE_Init failed";
    }
    return {};
  }();
  return failure;
}

/// hypre's description of its pending error, which is then cleared.
std::string hypreError(const char* what)
{
  char description[256] = {};
  HYPRE_DescribeError(HYPRE_GetError(), description);
  HYPRE_ClearAllErrors();
  return std::string(what) + " failed: " + description;
}

std::size_t csrBytes(const hypre_CSRMatrix* m)
{
  return static_cast<std::size_t>(hypre_CSRMatrixNumNonzeros(m)) * (sizeof(HYPRE_Complex) + sizeof(HYPRE_Int)) +
    static_cast<std::size_t>(hypre_CSRMatrixNumRows(m) + 1) * sizeof(HYPRE_Int);
}

std::size_t parCsrBytes(hypre_ParCSRMatrix* m)
{
  return m ? csrBytes(hypre_ParCSRMatrixDiag(m)) + csrBytes(hypre_ParCSRMatrixOffd(m)) : 0;
}

class BoomerAmg final : public CoordinateSolver
{
public:
  /// Starts MPI and hypre here, so that the factorizations' time is the hierarchy's alone:
  /// starting them is a cost of the process, not of a matrix (~0.5 s for OpenMPI's singleton
  /// start). A failure is reported by factor().
  BoomerAmg()
  {
    const std::lock_guard<std::mutex> hold(hypreLock());
    startHypre();
  }

  ~BoomerAmg() override
  {
    const std::lock_guard<std::mutex> hold(hypreLock());
    release();
  }

  std::string factor(const Eigen::SparseMatrix<double>& a) override
  {
    const std::lock_guard<std::mutex> hold(hypreLock());
    release();
    if (const std::string& failure = startHypre(); !failure.empty())
    {
      return failure;
    }
    Rows = static_cast<HYPRE_Int>(a.rows());
    if (Rows == 0) // every point fixed: nothing to precondition
    {
      Ready = true;
      return {};
    }
    std::string failure = build(a);
    if (failure.empty())
    {
      failure = setUp();
    }
    if (!failure.empty())
    {
      release();
      return failure;
    }
    Ready = true;
    return {};
  }

  bool factored() const override { return Ready; }

  void solve(Eigen::MatrixXd& columns) override
  {
    if (Rows == 0)
    {
      return;
    }
    const std::lock_guard<std::mutex> hold(hypreLock());
    double* b = hypre_VectorData(hypre_ParVectorLocalVector(RhsVector));
    double* x = hypre_VectorData(hypre_ParVectorLocalVector(SolutionVector));
    const std::size_t bytes = static_cast<std::size_t>(Rows) * sizeof(double);
    for (Eigen::Index c = 0; c < columns.cols(); ++c)
    {
      // One V-cycle from a zero guess: a fixed linear operator of the right-hand side.
      std::memcpy(b, columns.col(c).data(), bytes);
      std::memset(x, 0, bytes);
      HYPRE_BoomerAMGSolve(Solver, Operator, RhsVector, SolutionVector);
      std::memcpy(columns.col(c).data(), x, bytes);
    }
  }

  std::size_t bytes() const override { return Bytes; }

private:
  /// hypre's copy of A (rows in CSR: A is symmetric, so its columns are its rows) and the
  /// two vectors a V-cycle reads and writes.
  std::string build(const Eigen::SparseMatrix<double>& a)
  {
    Eigen::SparseMatrix<double, Eigen::RowMajor> rows = a;
    rows.makeCompressed();
    std::vector<HYPRE_Int> counts(static_cast<std::size_t>(Rows));
    std::vector<HYPRE_BigInt> rowIds(static_cast<std::size_t>(Rows));
    for (HYPRE_Int r = 0; r < Rows; ++r)
    {
      counts[static_cast<std::size_t>(r)] = rows.outerIndexPtr()[r + 1] - rows.outerIndexPtr()[r];
      rowIds[static_cast<std::size_t>(r)] = r;
    }
    const std::vector<HYPRE_BigInt> columnIds(rows.innerIndexPtr(), rows.innerIndexPtr() + rows.nonZeros());
    const HYPRE_BigInt last = Rows - 1;
    if (HYPRE_IJMatrixCreate(MPI_COMM_SELF, 0, last, 0, last, &Matrix) ||
      HYPRE_IJMatrixSetObjectType(Matrix, HYPRE_PARCSR) || HYPRE_IJMatrixSetRowSizes(Matrix, counts.data()) ||
      HYPRE_IJMatrixInitialize(Matrix) ||
      HYPRE_IJMatrixSetValues(Matrix, Rows, counts.data(), rowIds.data(), columnIds.data(), rows.valuePtr()) ||
      HYPRE_IJMatrixAssemble(Matrix) || HYPRE_IJMatrixGetObject(Matrix, reinterpret_cast<void**>(&Operator)))
    {
      return hypreError("hypre's assembly of the matrix");
    }
    for (auto [vector, object] : { std::pair{ &Rhs, &RhsVector }, std::pair{ &Solution, &SolutionVector } })
    {
      if (HYPRE_IJVectorCreate(MPI_COMM_SELF, 0, last, vector) ||
        HYPRE_IJVectorSetObjectType(*vector, HYPRE_PARCSR) || HYPRE_IJVectorInitialize(*vector) ||
        HYPRE_IJVectorAssemble(*vector) || HYPRE_IJVectorGetObject(*vector, reinterpret_cast<void**>(object)))
      {
        return hypreError("hypre's vectors");
      }
    }
    return {};
  }

  /// The hierarchy. Settings for A's kind of matrix (a 3D Laplacian-like stiffness plus a mass
  /// term), as a preconditioner (one cycle, no convergence test), chosen by CG iterations and
  /// time per step on a 69k-tet ellipsoid (bench_implicit's scene):
  /// - HMIS coarsening, strength threshold 0.25 (the usual choice for 3D scalar diffusion);
  ///   aggressive coarsening on the first level cut the hierarchy's memory by a third and each
  ///   V-cycle by ~10 %, but CG needed 15 iterations per Newton step instead of 12, which cost
  ///   as much as it saved; PMIS, or a threshold of 0.5, changed little;
  /// - extended+i interpolation truncated to 4 entries per row, which HMIS's sparse coarse
  ///   grids need to stay accurate;
  /// - one Gauss-Seidel sweep forward going down and one backward coming up, with Gaussian
  ///   elimination on the coarsest level: the cycle is symmetric. (hypre's "hybrid" sweep is
  ///   plain Gauss-Seidel in one process.) Its l1 variants (hypre's default) cost ~40 % more
  ///   per cycle for the same iterations; symmetric sweeps both ways cost more still, and
  ///   l1-Jacobi needed ~40 % more iterations.
  std::string setUp()
  {
    HYPRE_BoomerAMGCreate(&Solver);
    HYPRE_BoomerAMGSetPrintLevel(Solver, 0);
    HYPRE_BoomerAMGSetMaxIter(Solver, 1);
    HYPRE_BoomerAMGSetTol(Solver, 0.0);
    HYPRE_BoomerAMGSetCoarsenType(Solver, 10); // HMIS
    HYPRE_BoomerAMGSetAggNumLevels(Solver, 0);
    HYPRE_BoomerAMGSetStrongThreshold(Solver, 0.25);
    HYPRE_BoomerAMGSetInterpType(Solver, 6); // extended+i
    HYPRE_BoomerAMGSetPMaxElmts(Solver, 4);
    HYPRE_BoomerAMGSetCycleRelaxType(Solver, 3, 1); // Gauss-Seidel, forward, going down
    HYPRE_BoomerAMGSetCycleRelaxType(Solver, 4, 2); // and backward coming up
    HYPRE_BoomerAMGSetCycleRelaxType(Solver, 9, 3); // Gaussian elimination on the coarsest level
    HYPRE_BoomerAMGSetRelaxOrder(Solver, 0);
    HYPRE_BoomerAMGSetNumSweeps(Solver, 1);
    if (HYPRE_BoomerAMGSetup(Solver, Operator, RhsVector, SolutionVector))
    {
      return hypreError("BoomerAMG's set-up");
    }
    // The hierarchy's operators (A on every level, hypre's own copy of the finest included) and
    // interpolations, as stored (values and column indices, row starts).
    auto* data = reinterpret_cast<hypre_ParAMGData*>(Solver);
    const HYPRE_Int levels = hypre_ParAMGDataNumLevels(data);
    Bytes = 0;
    for (HYPRE_Int level = 0; level < levels; ++level)
    {
      Bytes += parCsrBytes(hypre_ParAMGDataAArray(data)[level]);
      if (level + 1 < levels)
      {
        Bytes += parCsrBytes(hypre_ParAMGDataPArray(data)[level]);
      }
    }
    return {};
  }

  void release()
  {
    if (Solver)
    {
      HYPRE_BoomerAMGDestroy(Solver);
    }
    for (HYPRE_IJVector* vector : { &Rhs, &Solution })
    {
      if (*vector)
      {
        HYPRE_IJVectorDestroy(*vector);
      }
      *vector = nullptr;
    }
    if (Matrix)
    {
      HYPRE_IJMatrixDestroy(Matrix);
    }
    Solver = nullptr;
    Matrix = nullptr;
    Operator = nullptr;
    RhsVector = SolutionVector = nullptr;
    Bytes = 0;
    Ready = false;
  }

  HYPRE_Int Rows = 0;
  HYPRE_IJMatrix Matrix = nullptr;
  HYPRE_ParCSRMatrix Operator = nullptr; ///< Matrix's object
  HYPRE_IJVector Rhs = nullptr, Solution = nullptr;
  HYPRE_ParVector RhsVector = nullptr, SolutionVector = nullptr; ///< their objects
  HYPRE_Solver Solver = nullptr;
  std::size_t Bytes = 0;
  bool Ready = false;
};

} // namespace

bool algebraicMultigridAvailable()
{
  return true;
}

void requireAlgebraicMultigrid() {}

std::unique_ptr<CoordinateSolver> makeAlgebraicMultigrid()
{
  return std::make_unique<BoomerAmg>();
}

#else

bool algebraicMultigridAvailable()
{
  return false;
}

void requireAlgebraicMultigrid()
{
  throw InvalidInputError("The AlgebraicMultigrid preconditioner needs hypre's BoomerAMG, which this build "
                          "does not have: install libhypre-dev and rebuild, or choose another preconditioner.");
}

std::unique_ptr<CoordinateSolver> makeAlgebraicMultigrid()
{
  requireAlgebraicMultigrid();
  return nullptr;
}

#endif

} // namespace softbody
