#include "vascsim/core/single_precision_factor.hpp"

#include <algorithm>
#include <stdexcept>

// The Fortran BLAS of the process (OpenBLAS through Debian's libblas.so.3 alternative; blas_control.hpp). The
// trailing lengths are gfortran's hidden character-argument lengths.
extern "C" {
void strsv_(const char* uplo, const char* trans, const char* diag, const int* n, const float* a,
            const int* lda, float* x, const int* incx, std::size_t, std::size_t, std::size_t);
void sgemv_(const char* trans, const int* m, const int* n, const float* alpha, const float* a, const int* lda,
            const float* x, const int* incx, const float* beta, float* y, const int* incy, std::size_t);
void strsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m,
            const int* n, const float* alpha, const float* a, const int* lda, float* b, const int* ldb,
            std::size_t, std::size_t, std::size_t, std::size_t);
void sgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k,
            const float* alpha, const float* a, const int* lda, const float* b, const int* ldb,
            const float* beta, float* c, const int* ldc, std::size_t, std::size_t);
}

namespace vascsim {

namespace {
constexpr int kOne = 1;  // (non-const BLAS arguments below are passed as const: the BLAS does not write them)
constexpr float kPlus = 1.0f, kMinus = -1.0f, kZero = 0.0f;
}  // namespace

void SinglePrecisionFactor::assign(const SupernodalFactorView& f) {
  if (f.n <= 0 || f.supernodes <= 0 || !f.perm || !f.super || !f.row_start || !f.value_start || !f.rows ||
      !f.values)
    throw std::invalid_argument("SinglePrecisionFactor: not a supernodal factor");
  n_ = f.n;
  const auto ns = static_cast<std::size_t>(f.supernodes);
  perm_.assign(f.perm, f.perm + n_);
  super_.assign(f.super, f.super + ns + 1);
  row_start_.assign(f.row_start, f.row_start + ns + 1);
  value_start_.assign(f.value_start, f.value_start + ns + 1);
  rows_.assign(f.rows, f.rows + row_start_.back());
  values_.resize(static_cast<std::size_t>(value_start_.back()));
  std::transform(f.values, f.values + value_start_.back(), values_.begin(),
                 [](double v) { return static_cast<float>(v); });
  int widest = 0;  // the most off-diagonal rows of a supernode: the size of the gather/scatter buffer
  for (std::size_t k = 0; k < ns; ++k)
    widest = std::max(widest, (row_start_[k + 1] - row_start_[k]) - (super_[k + 1] - super_[k]));
  work_.assign(static_cast<std::size_t>(widest), 0.0f);
  y_.assign(static_cast<std::size_t>(n_), 0.0f);
}

void SinglePrecisionFactor::forward(float* y) const {
  float* t = work_.data();
  const auto ns = super_.size() - 1;
  for (std::size_t k = 0; k < ns; ++k) {
    const int c0 = super_[k], nc = super_[k + 1] - c0;
    const int nr = row_start_[k + 1] - row_start_[k], m = nr - nc;
    const float* L = values_.data() + value_start_[k];
    float* yk = y + c0;
    strsv_("L", "N", "N", &nc, L, &nr, yk, &kOne, 1, 1, 1);  // the diagonal block
    if (m == 0) continue;
    // The rows below: t = L_below y_k in one BLAS call, then scattered once.
    sgemv_("N", &m, &nc, &kPlus, L + nc, &nr, yk, &kOne, &kZero, t, &kOne, 1);
    const int* r = rows_.data() + row_start_[k] + nc;
    for (int i = 0; i < m; ++i) y[r[i]] -= t[i];
  }
}

void SinglePrecisionFactor::backward(float* y) const {
  float* t = work_.data();
  for (std::size_t k = super_.size() - 1; k-- > 0;) {
    const int c0 = super_[k], nc = super_[k + 1] - c0;
    const int nr = row_start_[k + 1] - row_start_[k], m = nr - nc;
    const float* L = values_.data() + value_start_[k];
    float* yk = y + c0;
    if (m > 0) {
      const int* r = rows_.data() + row_start_[k] + nc;
      for (int i = 0; i < m; ++i) t[i] = y[r[i]];
      sgemv_("T", &m, &nc, &kMinus, L + nc, &nr, t, &kOne, &kPlus, yk, &kOne, 1);
    }
    strsv_("L", "T", "N", &nc, L, &nr, yk, &kOne, 1, 1, 1);
  }
}

void SinglePrecisionFactor::forward(float* Y, int columns) const {
  const auto ns = super_.size() - 1;
  for (std::size_t k = 0; k < ns; ++k) {
    const int c0 = super_[k], nc = super_[k + 1] - c0;
    const int nr = row_start_[k + 1] - row_start_[k], m = nr - nc;
    const float* L = values_.data() + value_start_[k];
    float* Yk = Y + c0;
    strsm_("L", "L", "N", "N", &nc, &columns, &kPlus, L, &nr, Yk, &n_, 1, 1, 1, 1);
    if (m == 0) continue;
    T_.resize(static_cast<std::size_t>(m) * static_cast<std::size_t>(columns));
    sgemm_("N", "N", &m, &columns, &nc, &kPlus, L + nc, &nr, Yk, &n_, &kZero, T_.data(), &m, 1, 1);
    const int* r = rows_.data() + row_start_[k] + nc;
    for (int j = 0; j < columns; ++j) {
      float* y = Y + static_cast<std::ptrdiff_t>(j) * n_;
      const float* t = T_.data() + static_cast<std::ptrdiff_t>(j) * m;
      for (int i = 0; i < m; ++i) y[r[i]] -= t[i];
    }
  }
}

void SinglePrecisionFactor::backward(float* Y, int columns) const {
  for (std::size_t k = super_.size() - 1; k-- > 0;) {
    const int c0 = super_[k], nc = super_[k + 1] - c0;
    const int nr = row_start_[k + 1] - row_start_[k], m = nr - nc;
    const float* L = values_.data() + value_start_[k];
    float* Yk = Y + c0;
    if (m > 0) {
      T_.resize(static_cast<std::size_t>(m) * static_cast<std::size_t>(columns));
      const int* r = rows_.data() + row_start_[k] + nc;
      for (int j = 0; j < columns; ++j) {
        const float* y = Y + static_cast<std::ptrdiff_t>(j) * n_;
        float* t = T_.data() + static_cast<std::ptrdiff_t>(j) * m;
        for (int i = 0; i < m; ++i) t[i] = y[r[i]];
      }
      sgemm_("T", "N", &nc, &columns, &m, &kMinus, L + nc, &nr, T_.data(), &m, &kPlus, Yk, &n_, 1, 1);
    }
    strsm_("L", "L", "T", "N", &nc, &columns, &kPlus, L, &nr, Yk, &n_, 1, 1, 1, 1);
  }
}

void SinglePrecisionFactor::solve(const Eigen::MatrixXd& B, Eigen::MatrixXd& X) const {
  if (empty()) throw std::logic_error("SinglePrecisionFactor::solve without a factor");
  if (B.rows() != n_)
    throw std::invalid_argument("SinglePrecisionFactor::solve: right-hand sides of the wrong size");
  const auto columns = static_cast<int>(B.cols());
  X.setZero(n_, B.cols());
  if (columns == 0) return;
  Y_.resize(static_cast<std::size_t>(n_) * static_cast<std::size_t>(columns));
  std::vector<double> scale(static_cast<std::size_t>(columns));
  for (int j = 0; j < columns; ++j) {
    const double s = B.col(j).cwiseAbs().maxCoeff();
    scale[static_cast<std::size_t>(j)] = s > 0.0 ? s : 1.0;
    float* y = Y_.data() + static_cast<std::ptrdiff_t>(j) * n_;
    for (int k = 0; k < n_; ++k)
      y[k] =
          static_cast<float>(B(perm_[static_cast<std::size_t>(k)], j) / scale[static_cast<std::size_t>(j)]);
  }
  forward(Y_.data(), columns);
  backward(Y_.data(), columns);
  for (int j = 0; j < columns; ++j) {
    const float* y = Y_.data() + static_cast<std::ptrdiff_t>(j) * n_;
    for (int k = 0; k < n_; ++k)
      X(perm_[static_cast<std::size_t>(k)], j) = scale[static_cast<std::size_t>(j)] * y[k];
  }
}

void SinglePrecisionFactor::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const {
  if (empty()) throw std::logic_error("SinglePrecisionFactor::solve without a factor");
  if (b.size() != n_)
    throw std::invalid_argument("SinglePrecisionFactor::solve: right-hand side of the wrong size");
  // Scaled into float's range by |b|_inf (a preconditioner's right-hand side may be of any magnitude).
  const double scale = b.cwiseAbs().maxCoeff();
  x.setZero(n_);
  if (!(scale > 0.0)) return;
  for (int k = 0; k < n_; ++k)
    y_[static_cast<std::size_t>(k)] = static_cast<float>(b[perm_[static_cast<std::size_t>(k)]] / scale);
  forward(y_.data());
  backward(y_.data());
  for (int k = 0; k < n_; ++k)
    x[perm_[static_cast<std::size_t>(k)]] = scale * y_[static_cast<std::size_t>(k)];
}

}  // namespace vascsim
