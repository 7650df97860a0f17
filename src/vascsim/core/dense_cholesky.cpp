#include "vascsim/core/dense_cholesky.hpp"

#include <cstddef>
#include <stdexcept>

// LAPACK's Fortran interface; the trailing length is that of the character argument (gfortran passes it).
extern "C" {
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info, std::size_t uplo_len);
void dpotrs_(const char* uplo, const int* n, const int* nrhs, const double* a, const int* lda, double* b,
             const int* ldb, int* info, std::size_t uplo_len);
void spotrf_(const char* uplo, const int* n, float* a, const int* lda, int* info, std::size_t uplo_len);
void spotrs_(const char* uplo, const int* n, const int* nrhs, const float* a, const int* lda, float* b,
             const int* ldb, int* info, std::size_t uplo_len);
}

namespace vascsim {

bool DenseCholesky::compute(Eigen::MatrixXd a) {
  if (a.rows() != a.cols()) throw std::invalid_argument("DenseCholesky: the matrix is not square");
  n_ = a.rows();
  const int n = static_cast<int>(n_);
  int info = 0;
  l_.resize(0, 0);
  lf_.resize(0, 0);
  if (single_ && n > 0) {
    lf_ = a.cast<float>();
    spotrf_("L", &n, lf_.data(), &n, &info, 1);
    if (info == 0) return valid_ = true;
    lf_.resize(0, 0);
    info = 0;
  }
  l_ = std::move(a);
  if (n > 0) dpotrf_("L", &n, l_.data(), &n, &info, 1);
  valid_ = info == 0;
  if (!valid_) {
    l_.resize(0, 0);
    n_ = 0;
  }
  return valid_;
}

Eigen::MatrixXd DenseCholesky::solve(const Eigen::MatrixXd& b) const {
  if (!valid_ || b.rows() != n_) throw std::invalid_argument("DenseCholesky: no factor of this size");
  const int n = static_cast<int>(n_), nrhs = static_cast<int>(b.cols());
  int info = 0;
  if (lf_.size() > 0) {
    Eigen::MatrixXf x = b.cast<float>();
    if (n > 0 && nrhs > 0) spotrs_("L", &n, &nrhs, lf_.data(), &n, x.data(), &n, &info, 1);
    return x.cast<double>();
  }
  Eigen::MatrixXd x = b;
  if (n > 0 && nrhs > 0) dpotrs_("L", &n, &nrhs, l_.data(), &n, x.data(), &n, &info, 1);
  return x;
}

Eigen::VectorXd DenseCholesky::solve(const Eigen::VectorXd& b) const {
  if (!valid_ || b.rows() != n_) throw std::invalid_argument("DenseCholesky: no factor of this size");
  const int n = static_cast<int>(n_), nrhs = 1;
  int info = 0;
  if (lf_.size() > 0) {
    Eigen::VectorXf x = b.cast<float>();
    if (n > 0) spotrs_("L", &n, &nrhs, lf_.data(), &n, x.data(), &n, &info, 1);
    return x.cast<double>();
  }
  Eigen::VectorXd x = b;
  if (n > 0) dpotrs_("L", &n, &nrhs, l_.data(), &n, x.data(), &n, &info, 1);
  return x;
}

}  // namespace vascsim
