#pragma once
// The preconditioner of the real-time equilibrium solver (docs/model/24-implicit.md): a supernodal sparse
// Cholesky factor (CHOLMOD) of the assembled point-primitive Hessian plus the inertia shift, restricted to
// the free nodes,
//     P = K(x_f) + M/h^2,      K = d^2U/dx^2 with every node's 9x9 tangent projected to PSD,
// built at a configuration x_f (the rest state, then wherever the solver refactors). Close to the Newton
// matrix, so preconditioned CG needs a handful of iterations while x stays near x_f (measured: 6-10 on the
// vein's Newton systems; a factor built at rest needs 100-250 at a 1.2 mm push, so it is refreshed).
//
// Building one (assembly + numeric factorisation) is the expensive part; it may run on another thread while
// an older factor serves the solves (ImplicitModel's asynchronous refactorisation). One object per factor:
// apply() and solve() write the factor's workspace, so a factor is used by one thread at a time.

#include <memory>

#include "vascsim/core/sparse_cholesky.hpp"
#include "vascsim/model/energy_hessian.hpp"
#include "vascsim/model/equilibrium_preconditioner.hpp"

namespace vascsim {

struct MeshlessFactorOptions {
  HessianStencil stencil = HessianStencil::Full;
  CholeskyOrdering ordering = CholeskyOrdering::Default;
  double inv_h2 = 0.0;  ///< the inertia shift M/h^2 (1/s^2); 0 for a static solve
  /// Solves (apply() and the multi-column solves of the contact compliances) run on a float copy of the
  /// factor (about half the time; core/single_precision_factor.hpp).
  bool single_precision_solves = true;
};

class MeshlessFactor final : public EquilibriumPreconditioner {
 public:
  /// Symbolic assembly only (no factor yet). The problem and `free` must outlive it.
  MeshlessFactor(const Problem& problem, const FreeDofs& free, const MeshlessFactorOptions& options);
  /// Assembles P at x and factorises it (the first call also analyses the pattern). Throws NumericalError if
  /// P is not positive definite.
  void refactor(const Vec3Array& x);
  bool ready() const { return cholesky_.factorized(); }
  bool apply(const Vec3Array& r, Vec3Array& z) const override;
  /// X = P^{-1} B on packed free-node vectors, several columns at once.
  void solve(const Eigen::MatrixXd& B, Eigen::MatrixXd& X) const;
  bool solve_columns(const Eigen::MatrixXd& B, Eigen::MatrixXd& X) const override {
    if (!ready()) return false;
    solve(B, X);
    return true;
  }
  long long version() const override { return version_; }
  nlohmann::json info() const override;
  /// Wall time of the last refactor (assembly + factorisation), s.
  double build_seconds() const { return build_s_; }
  const SparseCholeskyStats& stats() const { return cholesky_.stats(); }

 private:
  const FreeDofs& free_;
  MeshlessFactorOptions options_;
  std::vector<double> shift_;  // per node m_i / h^2, N/m
  EnergyHessian hessian_;
  mutable SparseCholesky cholesky_;
  mutable Eigen::VectorXd b_, y_;
  double build_s_ = 0.0;
  int builds_ = 0;
  long long version_ = 0;  // unique over every factor of the process (contact_correction.hpp caches by it)
};

}  // namespace vascsim
