#include "vascsim/model/meshless_factor.hpp"

#include <atomic>

#include "vascsim/core/stopwatch.hpp"

namespace vascsim {

namespace {
EnergyHessianOptions hessian_options(const MeshlessFactorOptions& o) {
  EnergyHessianOptions h;
  h.stencil = o.stencil;
  h.project_psd = true;          // a preconditioner must be SPD; SVK under compression is indefinite
  h.lower_triangle_only = true;  // all a Cholesky factorisation reads
  return h;
}
}  // namespace

MeshlessFactor::MeshlessFactor(const Problem& problem, const FreeDofs& free,
                               const MeshlessFactorOptions& options)
    : free_(free),
      options_(options),
      hessian_(problem.energy(), hessian_options(options), free.slot),
      cholesky_(SparseCholeskyOptions{options.ordering, true, options.single_precision_solves}) {
  if (options.inv_h2 > 0.0) {
    const auto& m = problem.discretization().masses();
    shift_.resize(m.size());
    for (std::size_t i = 0; i < m.size(); ++i) shift_[i] = m[i] * options.inv_h2;
  }
}

void MeshlessFactor::refactor(const Vec3Array& x) {
  const Stopwatch clock;
  hessian_.assemble(x, shift_);
  if (!cholesky_.analysed()) cholesky_.analyse(hessian_.matrix());
  cholesky_.factorize(hessian_.matrix());
  build_s_ = clock.seconds();
  ++builds_;
  static std::atomic<long long> factors_built{0};
  version_ = ++factors_built;
}

bool MeshlessFactor::apply(const Vec3Array& r, Vec3Array& z) const {
  if (!cholesky_.factorized()) return false;
  free_.pack(r, b_);
  cholesky_.solve(b_, y_);
  z.assign(r.size(), Vec3::Zero());
  free_.unpack(y_, z);
  return true;
}

void MeshlessFactor::solve(const Eigen::MatrixXd& B, Eigen::MatrixXd& X) const {
  cholesky_.solve(B, X);
}

nlohmann::json MeshlessFactor::info() const {
  const SparseCholeskyStats& s = cholesky_.stats();
  return {
      {"matrix", options_.stencil == HessianStencil::Full ? "meshless Hessian" : "compact meshless Hessian"},
      {"inertia_shift", options_.inv_h2 > 0.0},
      {"ordering", s.ordering},
      {"nnz_a", s.nnz_a},
      {"nnz_l", s.nnz_l},
      {"factorisations", builds_},
      {"last_build_s", build_s_},
      {"last_factorize_s", s.factorize_s}};
}

}  // namespace vascsim
