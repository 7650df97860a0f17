#include "vascsim/core/dense_cholesky.hpp"

#include <cstddef>
#include <stdexcept>

// LAPACK's Fortran interface; the trailing length is that of the character argument (gfortran passes it).
extern "C" {
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info, std::size_t uplo_len);
void dpotrs_(const char* uplo, const int* n, const int* nrhs, const double* a, const int* lda, double* b,
             const int* ldb, int* info, std::size_t uplo_len);
}

namespace vascsim {

bool DenseCholesky::compute(Eigen::MatrixXd a) {
  if (a.rows() != a.cols()) throw std::invalid_argument("DenseCholesky: the matrix is not square");
  l_ = std::move(a);
  const int n = static_cast<int>(l_.rows());
  int info = 0;
  if (n > 0) dpotrf_("L", &n, l_.data(), &n, &info, 1);
  valid_ = info == 0;
  if (!valid_) l_.resize(0, 0);
  return valid_;
}

Eigen::MatrixXd DenseCholesky::solve(const Eigen::MatrixXd& b) const {
  if (!valid_ || b.rows() != l_.rows()) throw std::invalid_argument("DenseCholesky: no factor of this size");
  Eigen::MatrixXd x = b;
  const int n = static_cast<int>(l_.rows()), nrhs = static_cast<int>(x.cols());
  int info = 0;
  if (n > 0 && nrhs > 0) dpotrs_("L", &n, &nrhs, l_.data(), &n, x.data(), &n, &info, 1);
  return x;
}

Eigen::VectorXd DenseCholesky::solve(const Eigen::VectorXd& b) const {
  if (!valid_ || b.rows() != l_.rows()) throw std::invalid_argument("DenseCholesky: no factor of this size");
  Eigen::VectorXd x = b;
  const int n = static_cast<int>(l_.rows()), nrhs = 1;
  int info = 0;
  if (n > 0) dpotrs_("L", &n, &nrhs, l_.data(), &n, x.data(), &n, &info, 1);
  return x;
}

}  // namespace vascsim
