#pragma once
// Sparse Cholesky factorisation A = L L^T of a symmetric positive definite matrix through CHOLMOD
// (SuiteSparse), for the preconditioner of the equilibrium solves: the fill-reducing ordering and the
// symbolic factor are computed once per pattern (analyse), the numbers as often as the values change
// (factorize), and solves reuse their workspace (no allocation per solve after the first).
//
// Only the lower triangle of A is read, so A may be stored whole or as its lower triangle
// (column-major, 32-bit indices, sorted: Eigen's default SparseMatrix<double> after makeCompressed()).
// The supernodal factorisation spends its time in dense BLAS kernels (dsyrk, dgemm, dtrsm, dpotrf), so its
// speed is the speed of the BLAS the process loads (blas_control.hpp).
//
// Not thread-safe: one object per thread (a solve writes the object's workspace).

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <string>

#include "vascsim/core/single_precision_factor.hpp"

namespace vascsim {

enum class CholeskyOrdering {
  Default,  ///< CHOLMOD's choice: AMD, and METIS when AMD's fill is high (fl/nnz(L) >= 500 and nnz(L)/nnz(A)
            ///< >= 5)
  Amd,      ///< approximate minimum degree
  Metis,    ///< METIS nested dissection
  Nesdis,   ///< CHOLMOD's nested dissection (node bisection + constrained minimum degree)
  Natural   ///< no reordering
};

/// "default", "amd", "metis", "nesdis", "natural".
std::string to_string(CholeskyOrdering ordering);

struct SparseCholeskyOptions {
  CholeskyOrdering ordering = CholeskyOrdering::Default;
  bool supernodal = true;  ///< false: CHOLMOD's simplicial (up-looking, no BLAS) LL^T
  /// Solves run on a float copy of the supernodal factor (single_precision_factor.hpp: half the memory
  /// traffic, about half the time; relative error about cond(A) * 1e-7). For preconditioners and the
  /// compliances built from them.
  bool single_precision_solves = false;
};

/// What the last analyse / factorize / solve did.
struct SparseCholeskyStats {
  std::string ordering;  ///< the ordering CHOLMOD used (after Default chose), as to_string
  bool supernodal = false;
  double nnz_a = 0;          ///< nonzeros of A's lower triangle
  double nnz_l = 0;          ///< nonzeros of L (fill of the exact factor, without supernodal padding)
  double stored_l = 0;       ///< numbers stored for L (supernodal: including the padding of amalgamation)
  double flops = 0;          ///< floating-point operations of one numeric factorisation (CHOLMOD's estimate)
  double analyse_s = 0.0;    ///< wall time of the last analyse, s
  double factorize_s = 0.0;  ///< wall time of the last factorize, s
  double solve_s = 0.0;      ///< wall time of the last solve, s
};

class SparseCholesky {
 public:
  explicit SparseCholesky(const SparseCholeskyOptions& options = {});
  ~SparseCholesky();
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  /// Ordering and symbolic factorisation of A's pattern (values ignored). Discards any previous factor.
  void analyse(const Eigen::SparseMatrix<double>& A);
  /// Numeric factorisation of A, whose pattern must be the analysed one (values may change; explicit zeros
  /// count as pattern). Throws NumericalError when A is not positive definite (naming the column where the
  /// factorisation broke down); the object then has no factor until the next successful factorize.
  void factorize(const Eigen::SparseMatrix<double>& A);
  /// analyse + factorize.
  void compute(const Eigen::SparseMatrix<double>& A);

  /// x = A^{-1} b (with the float copy of the factor when the options ask for it). Needs a factor
  /// (std::logic_error otherwise).
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x);
  /// X = A^{-1} B for several right-hand sides at once (the supernodal solve then runs in BLAS-3 kernels;
  /// with the float copy when the options ask for it).
  void solve(const Eigen::MatrixXd& B, Eigen::MatrixXd& X);

  bool analysed() const;
  bool factorized() const { return factorized_; }
  Eigen::Index rows() const { return rows_; }
  const SparseCholeskyStats& stats() const { return stats_; }
  const SparseCholeskyOptions& options() const { return options_; }

 private:
  void solve_columns(const double* b, Eigen::Index columns);  // into cm_->X
  void copy_to_single_precision();
  struct Cholmod;  // the CHOLMOD state (keeps cholmod.h out of this header)
  SparseCholeskyOptions options_;
  std::unique_ptr<Cholmod> cm_;
  Eigen::Index rows_ = 0;
  Eigen::Index nnz_analysed_ = -1;
  bool factorized_ = false;
  SparseCholeskyStats stats_;
  SinglePrecisionFactor single_;  // filled after each factorize when options_.single_precision_solves
};

}  // namespace vascsim
