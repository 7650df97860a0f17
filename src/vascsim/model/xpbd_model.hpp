#pragma once
// `xpbd`: the real-time pipeline of MODEL.md 3.3 (first cut, elastic option (B)). Per step of length
// step_s, n_sub substeps of length h = step_s / n_sub (Macklin et al. 2019, "Small Steps in Physics
// Simulation"), each:
//   free nodes:        v <- v + h f_ext/m ;  x_prev <- x ;  p <- x + h v
//   constrained nodes: p <- prescribed position (w = 0)
//   lambda <- 0 (once per substep: XPBD semantics, Macklin, Mueller, Chentanez 2016)
//   n_it times: the stable neo-Hookean pair (C_H, C_D) of every virtual tetrahedron (Macklin & Mueller
//     2021; constraints/tet_neo_hookean_constraint.hpp), projected Gauss-Seidel in graph-colour order
//     (tets of one colour share no node and run in parallel)
//   v <- (p - x_prev)/h, v <- v exp(-c h) (mass-proportional damping), x <- p.
// External loads (gravity, region forces) and prescribed displacements scale with the load factor,
// ramped linearly in time like ExplicitModel. The elastic energy is the tet neo-Hookean energy on the
// virtual tetrahedra, not the point-primitive energy of quasi_static/explicit (MODEL.md 3.3 (B)); its
// steady state converges to the P1 tet solution, not to quasi_static's meshless one.
// Deviations from the textbook pair: (C_H, C_D) are solved as one coupled 2x2 system per tet (sequential
// projection is not rest-stable), lambda' = lambda + mu (matches linear elasticity at small strain), and
// shear is only conditionally stable: h must stay below ~0.6 Delta_min / c_s (shear_stability_estimate()).

#include <vector>

#include "vascsim/model/model.hpp"

namespace vascsim {

struct XpbdSettings {
  double duration_s = 0.02;         ///< simulated time, s
  double ramp_time_s = 0.01;        ///< loads ramp linearly to full over this time, then hold (0: at once), s
  double output_interval_s = 1e-3;  ///< time between output points, s (rounded to whole steps)
  double step_s = 1e-3;             ///< step (haptic tick), s; split into `substeps`
  int substeps = 8;                 ///< n_sub per step
  int iterations = 1;               ///< n_it Gauss-Seidel sweeps per substep
  double damping_per_s = 10.0;      ///< mass-proportional damping c, 1/s (MODEL.md 3.4: 5-20)
};

class XpbdModel final : public Model {
 public:
  XpbdModel(const Problem& problem, const XpbdSettings& settings);
  std::string name() const override { return "xpbd"; }
  int num_steps() const override { return num_steps_; }
  StepReport advance(int k) override;
  const Vec3Array& positions() const override { return x_; }
  double load_factor() const override { return s_; }
  nlohmann::json info() const override;

  const Vec3Array& velocities() const { return v_; }
  /// Multipliers accumulated over the last substep, two per tet: [2T] = C_H, [2T+1] = C_D (kg m^2 for a
  /// dimensionless C; lambda/h^2 is the generalised constraint force).
  const std::vector<double>& multipliers() const { return lambda_; }
  double substep_length() const { return h_; }
  /// 0.5 Delta_min / c_s: above it the substep risks the shear instability (see the .cpp), s.
  double shear_stability_estimate() const { return h_shear_limit_; }
  int num_colours() const { return static_cast<int>(colour_start_.size()) - 1; }
  /// One substep to load factor s_next (public for tests and experiments).
  void substep(double s_next);

 private:
  double load_factor_at(double t) const;
  void project_tet(Index t);

  const Problem& problem_;
  XpbdSettings settings_;
  double step_ = 0.0, h_ = 0.0, h_shear_limit_ = 0.0;
  int num_steps_ = 0;
  long long substeps_done_ = 0;
  double t_ = 0.0, s_ = 0.0;
  double lame_lambda_ = 0.0;  ///< lambda' = lambda + mu of the hydrostatic constraint, Pa
  double shear_modulus_ = 0.0;

  Vec3Array x_, v_, x_prev_, p_, f_ext_;
  std::vector<double> inv_mass_;
  // Per tet: rest D_m^{-1}, compliances (1/J).
  std::vector<Mat3> dm_inv_;
  std::vector<double> alpha_h_, alpha_d_;
  std::vector<double> lambda_;
  // Tets sorted by colour: colour c holds colour_order_[colour_start_[c] .. colour_start_[c+1]).
  std::vector<Index> colour_order_, colour_start_;
};

}  // namespace vascsim
