#pragma once
// A dense Cholesky factor A = L L^T through LAPACK (dpotrf/dpotrs: OpenBLAS's blocked kernels where OpenBLAS
// is the LAPACK), for the dense blocks the solvers factor every frame: the wall multigrid's window round a
// tool (a few hundred nodes, about 570 unknowns on the real-time vein) took 5.4 ms with Eigen's LLT and 1.0
// ms this way on a 2.3 GHz Xeon (docs/performance.md, "Real time at hand speed").

#include <Eigen/Core>

namespace vascsim {

class DenseCholesky {
 public:
  /// Factors the symmetric positive definite `a` (only its lower triangle is read; the matrix is taken over).
  /// Returns false, and leaves no factor, when `a` is not positive definite.
  bool compute(Eigen::MatrixXd a);
  /// Whether a factor is held.
  bool valid() const { return valid_; }
  Eigen::Index rows() const { return l_.rows(); }
  /// A^{-1} b, for one right-hand side or several (the columns of b).
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;
  Eigen::MatrixXd solve(const Eigen::MatrixXd& b) const;

 private:
  Eigen::MatrixXd l_;  // L in the lower triangle (LAPACK's layout: column-major, leading dimension = rows)
  bool valid_ = false;
};

}  // namespace vascsim
