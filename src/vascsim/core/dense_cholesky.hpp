#pragma once
// A dense Cholesky factor A = L L^T through LAPACK (dpotrf/dpotrs: OpenBLAS's blocked kernels where OpenBLAS
// is the LAPACK), for the dense blocks the solvers factor every frame: the wall multigrid's window round a
// tool (a few hundred nodes, about 570 unknowns on the real-time vein) took 5.4 ms with Eigen's LLT and 1.0
// ms this way on a 2.3 GHz Xeon (docs/performance.md, "Real time at hand speed"). Optionally in float
// (spotrf/spotrs), as that window does.

#include <Eigen/Core>

namespace vascsim {

class DenseCholesky {
 public:
  /// single_precision: factor and solve in float (spotrf/spotrs), for a preconditioner's block: half the
  /// memory a solve streams (a 570-unknown factor then fits a 2 MiB L2 cache) and about half the flops'
  /// time, at float's 6e-8 relative rounding times the block's condition. A block float cannot factor (not
  /// positive definite in float) is factored in double instead.
  explicit DenseCholesky(bool single_precision = false) : single_(single_precision) {}
  /// Factors the symmetric positive definite `a` (only its lower triangle is read; the matrix is taken over).
  /// Returns false, and leaves no factor, when `a` is not positive definite.
  bool compute(Eigen::MatrixXd a);
  /// Whether a factor is held.
  bool valid() const { return valid_; }
  /// Whether the factor held is in float.
  bool in_single_precision() const { return valid_ && lf_.size() > 0; }
  Eigen::Index rows() const { return n_; }
  /// A^{-1} b, for one right-hand side or several (the columns of b).
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;
  Eigen::MatrixXd solve(const Eigen::MatrixXd& b) const;

 private:
  bool single_ = false;
  Eigen::Index n_ = 0;
  // L in the lower triangle (LAPACK's layout: column-major, leading dimension = rows), in double or float.
  Eigen::MatrixXd l_;
  Eigen::MatrixXf lf_;
  bool valid_ = false;
};

}  // namespace vascsim
