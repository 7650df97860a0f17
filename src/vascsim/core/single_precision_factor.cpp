#include "vascsim/core/single_precision_factor.hpp"

#include <algorithm>
#include <stdexcept>

// The Fortran BLAS of the process (OpenBLAS through Debian's libblas.so.3 alternative; blas_control.hpp). The
// trailing lengths are gfortran's hidden character-argument lengths.
extern "C" {
void strsv_(const char* uplo, const char* trans, const char* diag, const int* n, const float* a, const int* lda,
            float* x, const int* incx, std::size_t, std::size_t, std::size_t);
void sgemv_(const char* trans, const int* m, const int* n, const float* alpha, const float* a, const int* lda,
            const float* x, const int* incx, const float* beta, float* y, const int* incy, std::size_t);
}

namespace vascsim {

namespace {
constexpr int kOne = 1;
constexpr float kPlus = 1.0f, kMinus = -1.0f, kZero = 0.0f;
}  // namespace

void SinglePrecisionFactor::assign(const SupernodalFactorView& f) {
  if (f.n <= 0 || f.supernodes <= 0 || !f.perm || !f.super || !f.row_start || !f.value_start || !f.rows || !f.values)
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

void SinglePrecisionFactor::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const {
  if (empty()) throw std::logic_error("SinglePrecisionFactor::solve without a factor");
  if (b.size() != n_) throw std::invalid_argument("SinglePrecisionFactor::solve: right-hand side of the wrong size");
  // Scaled into float's range by |b|_inf (a preconditioner's right-hand side may be of any magnitude).
  const double scale = b.cwiseAbs().maxCoeff();
  x.setZero(n_);
  if (!(scale > 0.0)) return;
  for (int k = 0; k < n_; ++k) y_[static_cast<std::size_t>(k)] = static_cast<float>(b[perm_[static_cast<std::size_t>(k)]] / scale);
  forward(y_.data());
  backward(y_.data());
  for (int k = 0; k < n_; ++k) x[perm_[static_cast<std::size_t>(k)]] = scale * y_[static_cast<std::size_t>(k)];
}

}  // namespace vascsim
