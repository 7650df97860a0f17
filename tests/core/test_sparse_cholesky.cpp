// The CHOLMOD wrapper (core/sparse_cholesky.hpp): solves to rounding for every ordering, refactors on a
// fixed pattern, reads only the lower triangle, and refuses a matrix that is not positive definite with
// a clear error; the BLAS queries of core/blas_control.hpp.

#include <gtest/gtest.h>

#include <cstdlib>
#include <random>

#include "support/test_support.hpp"
#include "vascsim/core/blas_control.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/core/sparse_cholesky.hpp"

namespace vascsim {
namespace {

// 7-point Laplacian on an n^3 grid plus `shift` on the diagonal (symmetric; positive definite for shift >
// -the smallest Laplacian eigenvalue, 6 - 6 cos(pi/(n+1)) ~ 0.18 for n = 12).
Eigen::SparseMatrix<double> laplacian(int n, double shift) {
  std::vector<Eigen::Triplet<double>> t;
  auto id = [n](int i, int j, int k) { return (k * n + j) * n + i; };
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int r = id(i, j, k);
        t.emplace_back(r, r, 6.0 + shift);
        if (i > 0) t.emplace_back(r, id(i - 1, j, k), -1.0);
        if (i + 1 < n) t.emplace_back(r, id(i + 1, j, k), -1.0);
        if (j > 0) t.emplace_back(r, id(i, j - 1, k), -1.0);
        if (j + 1 < n) t.emplace_back(r, id(i, j + 1, k), -1.0);
        if (k > 0) t.emplace_back(r, id(i, j, k - 1), -1.0);
        if (k + 1 < n) t.emplace_back(r, id(i, j, k + 1), -1.0);
      }
  Eigen::SparseMatrix<double> A(n * n * n, n * n * n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

Eigen::VectorXd random_vector(Eigen::Index n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  Eigen::VectorXd v(n);
  for (Eigen::Index i = 0; i < n; ++i) v[i] = uni(rng);
  return v;
}

double relative_residual(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& x,
                         const Eigen::VectorXd& b) {
  return (A * x - b).norm() / b.norm();
}

TEST(SparseCholesky, SolvesToRoundingWithEveryOrderingSupernodalAndSimplicial) {
  const Eigen::SparseMatrix<double> A = laplacian(12, 0.01);
  const Eigen::VectorXd b = random_vector(A.rows(), 1);
  for (CholeskyOrdering ord : {CholeskyOrdering::Default, CholeskyOrdering::Amd, CholeskyOrdering::Metis,
                               CholeskyOrdering::Nesdis, CholeskyOrdering::Natural})
    for (bool super : {true, false}) {
      SparseCholesky chol({ord, super});
      chol.compute(A);
      Eigen::VectorXd x;
      chol.solve(b, x);
      const double res = relative_residual(A, x, b);
      const std::string what = to_string(ord) + (super ? " supernodal" : " simplicial");
      // cond(A) ~ 12 / 0.19 ~ 65: a backward-stable Cholesky gives ~cond * eps ~ 1e-14. 1e-12.
      EXPECT_LE(res, 1e-12) << what;
      EXPECT_EQ(chol.stats().supernodal, super) << what;
      EXPECT_GE(chol.stats().nnz_l, chol.stats().nnz_a) << what;  // L holds at least A's lower triangle
      EXPECT_GT(chol.stats().flops, 0.0) << what;
      if (ord == CholeskyOrdering::Amd) {
        EXPECT_EQ(chol.stats().ordering, "amd");
      }
      if (ord == CholeskyOrdering::Metis) {
        EXPECT_EQ(chol.stats().ordering, "metis");
      }
      if (ord == CholeskyOrdering::Nesdis) {
        EXPECT_EQ(chol.stats().ordering, "nesdis");
      }
      test::record("nnz_l_" + to_string(ord) + (super ? "_super" : "_simpl"), chol.stats().nnz_l);
    }
}

// The float copy of the factor (single_precision_factor.hpp) against the double solve. A float solve has a
// relative error of about cond(A) * 6e-8 (rounding of L and of every operation): cond(A) = (12 + 0.5) /
// (0.18 + 0.5) ~ 18 here, so 1e-5 leaves a margin of about 10 and still fails a solve that mixes up a
// permutation or a supernode (errors of order 1). Every ordering: the permutations differ.
TEST(SparseCholesky, SinglePrecisionSolvesAgreeWithTheDoubleFactorToFloatRounding) {
  const Eigen::SparseMatrix<double> A = laplacian(12, 0.5);
  const Eigen::VectorXd b = random_vector(A.rows(), 7);
  for (CholeskyOrdering ord : {CholeskyOrdering::Amd, CholeskyOrdering::Metis, CholeskyOrdering::Natural}) {
    SparseCholesky exact({ord, true, false}), single({ord, true, true});
    exact.compute(A);
    single.compute(A);
    Eigen::VectorXd x, y;
    exact.solve(b, x);
    single.solve(b, y);
    EXPECT_LE((y - x).norm() / x.norm(), 1e-5) << to_string(ord);
    EXPECT_GT((y - x).norm(), 0.0) << "the float path was not taken";
    // Refactoring new values refreshes the copy.
    const Eigen::SparseMatrix<double> B = laplacian(12, 2.0);
    exact.factorize(B);
    single.factorize(B);
    exact.solve(b, x);
    single.solve(b, y);
    EXPECT_LE((y - x).norm() / x.norm(), 1e-5) << to_string(ord) << " after refactoring";
    // Several right-hand sides at once (strsm/sgemm per supernode), columns of very different sizes.
    Eigen::MatrixXd Bs(b.size(), 3), Xe, Xs;
    Bs << b, 1e-6 * random_vector(b.size(), 8), 1e6 * random_vector(b.size(), 9);
    exact.solve(Bs, Xe);  // exact's options: double
    single.solve(Bs, Xs);
    for (int j = 0; j < 3; ++j)
      EXPECT_LE((Xs.col(j) - Xe.col(j)).norm() / Xe.col(j).norm(), 1e-5) << to_string(ord) << " column " << j;
  }
}

TEST(SparseCholesky, ReadsOnlyTheLowerTriangle) {
  const Eigen::SparseMatrix<double> A = laplacian(8, 0.5);
  Eigen::SparseMatrix<double> lower = A.triangularView<Eigen::Lower>();
  lower.makeCompressed();
  Eigen::SparseMatrix<double> spoiled = A;  // garbage in the strict upper triangle must not matter
  for (int j = 0; j < spoiled.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(spoiled, j); it; ++it)
      if (it.row() < j) it.valueRef() = 1e6;
  const Eigen::VectorXd b = random_vector(A.rows(), 2);
  Eigen::VectorXd x_full, x_lower, x_spoiled;
  SparseCholesky a, l, s;
  a.compute(A);
  l.compute(lower);
  s.compute(spoiled);
  a.solve(b, x_full);
  l.solve(b, x_lower);
  s.solve(b, x_spoiled);
  // Same numbers go into the factorisation: identical results.
  EXPECT_EQ((x_full - x_lower).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((x_full - x_spoiled).cwiseAbs().maxCoeff(), 0.0);
}

TEST(SparseCholesky, RefactorsNewValuesOnTheAnalysedPattern) {
  Eigen::SparseMatrix<double> A = laplacian(10, 0.1);
  SparseCholesky chol;
  chol.analyse(A);
  chol.factorize(A);
  const Eigen::VectorXd b = random_vector(A.rows(), 3);
  // New values, same pattern: scale and shift.
  for (int j = 0; j < A.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it)
      it.valueRef() *= it.row() == j ? 3.0 : 2.0;
  chol.factorize(A);
  Eigen::VectorXd x;
  chol.solve(b, x);
  // cond ~ 12 / 0.3 ~ 40; see the first test. 1e-12.
  EXPECT_LE(relative_residual(A, x, b), 1e-12);
  // A different pattern is refused.
  const Eigen::SparseMatrix<double> other = laplacian(9, 0.1);
  EXPECT_THROW(chol.factorize(other), std::invalid_argument);
}

TEST(SparseCholesky, RefusesAnIndefiniteMatrixClearlyAndRecovers) {
  // Shift -1 pushes the lowest Laplacian eigenvalues (~0.18 on 12^3) below zero: symmetric indefinite.
  const Eigen::SparseMatrix<double> bad = laplacian(12, -1.0);
  const Eigen::SparseMatrix<double> good = laplacian(12, 0.0);
  for (bool super : {true, false}) {
    SparseCholesky chol({CholeskyOrdering::Default, super});
    chol.analyse(bad);
    try {
      chol.factorize(bad);
      ADD_FAILURE() << "an indefinite matrix was factorised";
    } catch (const NumericalError& e) {
      EXPECT_NE(std::string(e.what()).find("not positive definite"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(chol.factorized());
    Eigen::VectorXd x;
    EXPECT_THROW(chol.solve(Eigen::VectorXd::Ones(bad.rows()), x), std::logic_error);
    // The same pattern with positive definite values factorises again.
    chol.factorize(good);
    const Eigen::VectorXd b = random_vector(good.rows(), 4);
    chol.solve(b, x);
    // cond ~ 12 / 0.18 ~ 65. 1e-12.
    EXPECT_LE(relative_residual(good, x, b), 1e-12);
  }
}

TEST(SparseCholesky, BlasIsFoundAndItsThreadsCanBeSet) {
  // CHOLMOD brings a BLAS into the process; with OpenBLAS the thread count is settable, with the
  // reference BLAS there is nothing to set and it runs on one thread.
  const std::string lib = blas_library();
  EXPECT_FALSE(lib.empty());
  ::testing::Test::RecordProperty("blas_library", lib);
  const bool settable = set_blas_threads(1);
  EXPECT_EQ(blas_threads(), 1);
  EXPECT_EQ(settable, !blas_config().empty());
  ::testing::Test::RecordProperty("blas_config", blas_config());
}

// OpenBLAS falls back to its generic Prescott kernels on CPUs newer than its table; the program then restarts
// with the kernels of the instruction sets the CPU has. A core OpenBLAS chose itself, or one the user set, is
// never overridden, and an override names kernels the CPU can run.
TEST(SparseCholesky, BlasCoreOverrideOnlyReplacesTheGenericFallback) {
  const char* set = std::getenv("OPENBLAS_CORETYPE");
  const std::string saved = set ? set : "";
  setenv("OPENBLAS_CORETYPE", "Haswell", 1);
  EXPECT_EQ(blas_core_override(), "");  // the user's choice stands
  unsetenv("OPENBLAS_CORETYPE");
  const std::string core = blas_core_override();
  ::testing::Test::RecordProperty("blas_core_override", core);
  if (!core.empty()) {
    const std::string config = blas_config();
    EXPECT_NE(config.find("Prescott"), std::string::npos) << config;  // only the generic fallback
    __builtin_cpu_init();
    if (core == "SkylakeX")
      EXPECT_TRUE(__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw"));
    else
      EXPECT_TRUE(core == "Haswell" && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))
          << core;
  }
  if (set) setenv("OPENBLAS_CORETYPE", saved.c_str(), 1);
}

}  // namespace
}  // namespace vascsim
