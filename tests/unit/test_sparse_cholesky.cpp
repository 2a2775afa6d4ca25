// The sparse Cholesky factorization both backends share an interface for: solves against a
// dense reference, several right-hand sides at once, refactoring with the same pattern, and a
// matrix that is not positive definite reported rather than factored.
#include "softbody/common/sparse_cholesky.h"

#include <Eigen/Cholesky>
#include <Eigen/SparseCore>
#include <gtest/gtest.h>

#include <vector>

using namespace softbody;

namespace
{

/// The 7-point Laplacian of an n^3 grid plus `shift` on the diagonal: SPD for shift > 0, and
/// with a wide enough band that the orderings and supernodes matter.
Eigen::SparseMatrix<double> gridLaplacian(int n, double shift)
{
  std::vector<Eigen::Triplet<double>> entries;
  const auto index = [n](int i, int j, int k) { return (k * n + j) * n + i; };
  for (int k = 0; k < n; ++k)
  {
    for (int j = 0; j < n; ++j)
    {
      for (int i = 0; i < n; ++i)
      {
        const int row = index(i, j, k);
        entries.emplace_back(row, row, 6.0 + shift);
        const int neighbours[3][3] = { { i + 1, j, k }, { i, j + 1, k }, { i, j, k + 1 } };
        for (const auto& q : neighbours)
        {
          if (q[0] < n && q[1] < n && q[2] < n)
          {
            const int column = index(q[0], q[1], q[2]);
            entries.emplace_back(row, column, -1.0);
            entries.emplace_back(column, row, -1.0);
          }
        }
      }
    }
  }
  Eigen::SparseMatrix<double> a(n * n * n, n * n * n);
  a.setFromTriplets(entries.begin(), entries.end());
  return a;
}

} // namespace

TEST(SparseCholesky, BothBackendsSolveThreeRightHandSidesAsTheDenseFactorDoes)
{
  const Eigen::SparseMatrix<double> a = gridLaplacian(9, 0.05);
  const Eigen::MatrixXd b = Eigen::MatrixXd::Random(a.rows(), 3);
  const Eigen::MatrixXd reference = Eigen::MatrixXd(a).llt().solve(b);
  for (CholeskyBackend backend : { CholeskyBackend::CholmodSupernodal, CholeskyBackend::EigenSimplicial })
  {
    SparseCholesky cholesky(backend);
    ASSERT_EQ(cholesky.factor(a), "") << choleskyBackendName(backend);
    ASSERT_TRUE(cholesky.factored());
    Eigen::MatrixXd x = b;
    cholesky.solve(x);
    EXPECT_LT((x - reference).norm(), 1e-10 * reference.norm()) << choleskyBackendName(backend);
    EXPECT_GE(cholesky.factorNonZeros(), static_cast<std::size_t>(a.rows()));
    EXPECT_GT(cholesky.factorBytes(), 0u);
  }
}

TEST(SparseCholesky, RefactoringWithNewValuesSolvesTheNewMatrix)
{
  for (CholeskyBackend backend : { CholeskyBackend::CholmodSupernodal, CholeskyBackend::EigenSimplicial })
  {
    SparseCholesky cholesky(backend);
    ASSERT_EQ(cholesky.factor(gridLaplacian(6, 0.1)), "");
    const Eigen::SparseMatrix<double> stiffer = gridLaplacian(6, 3.0);
    ASSERT_EQ(cholesky.factor(stiffer), ""); // same pattern: the analysis is reused
    const Eigen::MatrixXd b = Eigen::MatrixXd::Random(stiffer.rows(), 2);
    Eigen::MatrixXd x = b;
    cholesky.solve(x);
    EXPECT_LT((stiffer * x - b).norm(), 1e-12 * b.norm()) << choleskyBackendName(backend);
  }
}

TEST(SparseCholesky, AMatrixThatIsNotPositiveDefiniteIsReportedNotFactored)
{
  // Shift -1 puts the Laplacian's smallest eigenvalues (near 0) below zero.
  const Eigen::SparseMatrix<double> indefinite = gridLaplacian(5, -1.0);
  for (CholeskyBackend backend : { CholeskyBackend::CholmodSupernodal, CholeskyBackend::EigenSimplicial })
  {
    SparseCholesky cholesky(backend);
    const std::string failure = cholesky.factor(indefinite);
    EXPECT_NE(failure.find("not positive definite"), std::string::npos)
      << choleskyBackendName(backend) << ": " << failure;
    EXPECT_FALSE(cholesky.factored());
    // And it recovers: a good matrix afterwards factors.
    EXPECT_EQ(cholesky.factor(gridLaplacian(5, 0.1)), "");
    EXPECT_TRUE(cholesky.factored());
  }
}

// Every point fixed leaves no unknowns: the empty matrix is factored and solved as nothing.
TEST(SparseCholesky, AnEmptyMatrixIsFactoredAndSolvedAsNothing)
{
  for (CholeskyBackend backend : { CholeskyBackend::CholmodSupernodal, CholeskyBackend::EigenSimplicial })
  {
    SparseCholesky cholesky(backend);
    EXPECT_EQ(cholesky.factor(Eigen::SparseMatrix<double>(0, 0)), "") << choleskyBackendName(backend);
    EXPECT_TRUE(cholesky.factored());
    Eigen::MatrixXd nothing(0, 3);
    cholesky.solve(nothing);
    EXPECT_EQ(cholesky.factorBytes(), 0u);
  }
}
