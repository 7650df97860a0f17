#pragma once
// A single-precision copy of a supernodal Cholesky factor A = P^T L L^T P, for fast triangular solves.
//
// Why: a preconditioner's back-solve with one right-hand side reads every number of L once forward and once
// backward, and does two flops per number read, so it runs at the speed of memory, not of the processor. On
// the vein's meshless Hessian (5,712 nodes) L holds 9.3 million numbers (74 MB in double) and one solve takes
// about 8-11 ms. Stored in float, L is half the bytes and the solve about half the time. The solve runs in
// float (the BLAS's strsv/sgemv per supernode), so its relative error is about cond(A) * 1e-7: for a
// preconditioner, whose job is to be close to the inverse, that is as good as exact (measured: the same PCG
// iteration counts).
//
// Layout (CHOLMOD's supernodal factor, in its own words: super, pi, px, s, x): supernode k holds the columns
// super[k] .. super[k+1]-1 of L as one dense column-major block of pi[k+1]-pi[k] rows (their row indices are
// s[pi[k]] ..), the first rows being the block's own columns (a lower triangle), stored from x[px[k]].

#include <Eigen/Core>
#include <vector>

namespace vascsim {

/// The supernodal structure and numbers of a factor, as CHOLMOD stores them (int indices).
struct SupernodalFactorView {
  int n = 0;  ///< rows of A
  int supernodes = 0;
  const int* perm = nullptr;         ///< perm[k] = the row of A that is k-th in the factor's order (n)
  const int* super = nullptr;        ///< first column of each supernode (supernodes + 1)
  const int* row_start = nullptr;    ///< pi: start of each supernode's row indices (supernodes + 1)
  const int* value_start = nullptr;  ///< px: start of each supernode's numbers (supernodes + 1)
  const int* rows = nullptr;         ///< s: row indices
  const double* values = nullptr;    ///< x: the numbers, column-major per supernode
};

class SinglePrecisionFactor {
 public:
  /// Copies the factor (its numbers rounded to float). Reuses the storage of an earlier copy.
  void assign(const SupernodalFactorView& factor);
  bool empty() const { return n_ == 0; }
  Eigen::Index rows() const { return n_; }
  /// x = A^{-1} b with the float factor (b scaled into float's range first). x may not alias b.
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const;
  /// X = A^{-1} B for several right-hand sides at once: per supernode the BLAS-3 strsm and sgemm, each column
  /// scaled into float's range by its own largest entry.
  void solve(const Eigen::MatrixXd& B, Eigen::MatrixXd& X) const;
  /// Bytes held for L's numbers.
  std::size_t value_bytes() const { return values_.size() * sizeof(float); }

 private:
  void forward(float* y) const;               // y <- L^{-1} y (factor order)
  void backward(float* y) const;              // y <- L^{-T} y
  void forward(float* Y, int columns) const;  // the same on n x columns, column-major
  void backward(float* Y, int columns) const;
  int n_ = 0;
  std::vector<int> perm_, super_, row_start_, value_start_, rows_;
  std::vector<float> values_;
  mutable std::vector<float> work_, y_;  // solve workspace: one object per thread
  mutable std::vector<float> Y_, T_;     // the same for several right-hand sides
};

}  // namespace vascsim
