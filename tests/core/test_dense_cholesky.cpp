// core/dense_cholesky: LAPACK's dense Cholesky factor and solves against the matrix itself.
#include "vascsim/core/dense_cholesky.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

namespace vascsim {
namespace {

Eigen::MatrixXd random_spd(Eigen::Index n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  Eigen::MatrixXd B(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) B(i, j) = uni(rng);
  return B * B.transpose() + static_cast<double>(n) * Eigen::MatrixXd::Identity(n, n);
}

// A = B B^T + n I has a condition number of a few units: a backward-stable Cholesky solves to about cond *
// eps ~ 1e-15; 1e-12 leaves room and still fails for any wrong triangle or transposed solve (errors of order
// 1).
TEST(DenseCholesky, SolvesOneAndSeveralRightHandSidesReadingTheLowerTriangle) {
  const Eigen::Index n = 300;  // above LAPACK's block size, so that the blocked path runs
  const Eigen::MatrixXd A = random_spd(n, 1);
  Eigen::MatrixXd lower_only = A.triangularView<Eigen::Lower>();
  lower_only.triangularView<Eigen::StrictlyUpper>().setConstant(1e6);  // never read
  DenseCholesky chol;
  ASSERT_TRUE(chol.compute(lower_only));
  ASSERT_TRUE(chol.valid());
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
  const Eigen::VectorXd x = chol.solve(b);
  EXPECT_LT((A * x - b).norm() / b.norm(), 1e-12);
  const Eigen::MatrixXd B = random_spd(n, 2).leftCols(5);
  const Eigen::MatrixXd X = chol.solve(B);
  EXPECT_LT((A * X - B).norm() / B.norm(), 1e-12);
}

// In float (a preconditioner's block): the same solves to float's rounding, about cond * 6e-8 ~ 1e-6 on this
// matrix (tolerance 1e-5; a wrong triangle or transposed solve still errs by order 1), the factor held in
// float.
TEST(DenseCholesky, InSinglePrecisionSolvesToFloatsRounding) {
  const Eigen::Index n = 300;
  const Eigen::MatrixXd A = random_spd(n, 1);
  Eigen::MatrixXd lower_only = A.triangularView<Eigen::Lower>();
  lower_only.triangularView<Eigen::StrictlyUpper>().setConstant(1e6);  // never read
  DenseCholesky chol(true);
  ASSERT_TRUE(chol.compute(lower_only));
  EXPECT_TRUE(chol.in_single_precision());
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
  EXPECT_LT((A * chol.solve(b) - b).norm() / b.norm(), 1e-5);
  const Eigen::MatrixXd B = random_spd(n, 2).leftCols(5);
  EXPECT_LT((A * chol.solve(B) - B).norm() / B.norm(), 1e-5);
}

// A block positive definite in double that rounding to float makes singular ([[1, 1 - 1e-9], [1 - 1e-9, 1]]:
// 1 - 1e-9 is 1 in float) is factored in double instead, and solved to double's cond * eps ~ 1e-7 (tolerance
// 1e-5; the float factor, were it taken, would have no solution at all).
TEST(DenseCholesky, ABlockFloatCannotFactorIsFactoredInDouble) {
  Eigen::Matrix2d A;
  A << 1.0, 1.0 - 1e-9, 1.0 - 1e-9, 1.0;
  DenseCholesky chol(true);
  ASSERT_TRUE(chol.compute(A));
  EXPECT_FALSE(chol.in_single_precision());
  const Eigen::Vector2d b(1.0, -1.0);
  const Eigen::VectorXd x = chol.solve(Eigen::VectorXd(b));
  EXPECT_LT((A * x - b).norm() / b.norm(), 1e-5);
}

TEST(DenseCholesky, AMatrixThatIsNotPositiveDefiniteLeavesNoFactor) {
  Eigen::MatrixXd A = random_spd(50, 3);
  A(20, 20) = -1.0;
  DenseCholesky chol;
  EXPECT_FALSE(chol.compute(A));
  EXPECT_FALSE(chol.valid());
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(50);
  EXPECT_THROW(chol.solve(ones), std::invalid_argument);
}

}  // namespace
}  // namespace vascsim
