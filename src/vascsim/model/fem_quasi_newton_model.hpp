#pragma once
// `fem_quasi_newton`: implicit hyperelastic finite elements accelerated by a quasi-Newton method, our reading
// of
//   X. H. Liu, J. F. Yao, "Modelling and simulation of vascular tissue based on finite element method", Proc.
//   ICISCE 2018, Zhengzhou, China, pp. 336-340 (the paper's baseline [23]: "an optimized FEM in which a
//   quasi-Newton algorithm accelerates the deformation computation"; the paper itself could not be
//   retrieved),
// with the method of
//   T. Liu, S. Bouaziz, L. Kavan, "Quasi-Newton methods for real-time simulation of hyperelastic materials",
//   ACM Transactions on Graphics 36(3), 23, 2017.
// INTERPRETATION where [23] is silent (docs/model/25-baselines.md section 25.3). On the virtual tetrahedra
// (P1, rest D_m^{-1}, volume V_T), the compressible neo-Hookean energy
//   psi(F) = mu/2 (tr F^T F - 3) - mu ln J + lambda/2 (ln J)^2     (lambda, mu from the scene's E and nu),
// backward Euler as a minimisation per frame h:
//   x_{n+1} = argmin g(x) = 1/(2 h^2) |x - y|_M^2 + sum_T V_T psi(F_T(x)) - f_ext . x,   y = x_n + h v_n,
// by L-BFGS (history m) whose initial inverse Hessian is a prefactored (M/h^2 + K_0)^{-1}, K_0 the linear tet
// stiffness at rest (tet_stiffness.hpp; CHOLMOD, sparse_cholesky.hpp): Liu et al.'s choice of a constant,
// prefactored initial Hessian. Armijo backtracking (c = 1e-4; an inverted tet has infinite energy).
// Prescribed nodes are held; tool contacts by the active set (contact_active_set.hpp). v_{n+1} = (x_{n+1} -
// x_n)/h.

#include <deque>
#include <memory>

#include "vascsim/core/sparse_cholesky.hpp"
#include "vascsim/model/contact_active_set.hpp"
#include "vascsim/model/dynamic_baseline.hpp"

namespace vascsim {

struct FemQuasiNewtonSettings {
  BaselineFrames frames;
  int history = 6;              ///< L-BFGS pairs kept (Liu et al.: 5-7)
  int max_iterations = 20;      ///< per frame
  double rel_tolerance = 1e-6;  ///< stop when |grad g| <= this * |grad g| at the frame's start (free dofs)
  double damping_per_s = 0.0;   ///< mass-proportional damping on the velocity, 1/s
};

FemQuasiNewtonSettings read_fem_quasi_newton_settings(JsonReader& block);
ModelEntry fem_quasi_newton_model_entry();

class FemQuasiNewtonModel final : public DynamicBaseline {
 public:
  FemQuasiNewtonModel(const Problem& problem, const FemQuasiNewtonSettings& settings);
  ~FemQuasiNewtonModel() override;
  /// Elastic energy sum_T V_T psi(F_T(x)) (J; +inf if a tet is inverted) and, if grad is not null, its
  /// gradient.
  double elastic_energy(const Vec3Array& x, Vec3Array* grad) const;

 protected:
  StepReport frame(double s_prev, double s_next) override;
  nlohmann::json method_info() const override;

 private:
  double objective(const Vec3Array& x, Vec3Array& grad) const;  // g and its (unfiltered) gradient
  void direction(const Vec3Array& grad, Vec3Array& d);          // L-BFGS two-loop, filtered
  int minimise(Vec3Array& x, Vec3Array& grad, double& g, double tolerance);

  FemQuasiNewtonSettings settings_;
  FreeDofs free_;
  ContactActiveSet contacts_;
  std::unique_ptr<SparseCholesky> factor_;
  std::vector<Mat3> dm_inv_;
  std::vector<double> rest_volume_, mass_;
  double lambda_ = 0.0, mu_ = 0.0;
  Vec3Array y_, f_ext_;
  std::deque<std::pair<Vec3Array, Vec3Array>> pairs_;  // (s_k, y_k)
  long long iterations_total_ = 0;
  double last_reduction_ = 0.0;
};

}  // namespace vascsim
