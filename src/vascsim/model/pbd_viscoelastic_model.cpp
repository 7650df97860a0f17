#include "vascsim/model/pbd_viscoelastic_model.hpp"

#include <spdlog/spdlog.h>
#include <algorithm>
#include <cmath>

#include "vascsim/constraints/tet_volume_constraint.hpp"

namespace vascsim {

PbdViscoelasticSettings read_pbd_viscoelastic_settings(JsonReader& b) {
  PbdViscoelasticSettings s;
  s.frames = read_baseline_frames(b);
  s.nonlinearity = b.number("nonlinearity", 2.0, 0.0, 1e4);
  s.damping_ratio = b.number("damping_ratio", 0.05, 0.0, 10.0);
  s.damping_per_s = b.number("damping_per_s", 0.0, 0.0, 1e7);
  s.iterations = b.integer("iterations", 2, 0, 1000);
  s.time_step_safety = b.number("time_step_safety", 0.5, 0.01, 1.0);
  s.max_strain = b.number("max_strain", 0.3, 0.0, 10.0);
  b.finish();
  return s;
}

ModelEntry pbd_viscoelastic_model_entry() {
  return make_baseline_entry<PbdViscoelasticModel, PbdViscoelasticSettings>(
      "pbd_viscoelastic",
      "baseline [16] Xu et al. 2018 (interpretation): nonlinear Kelvin-Voigt springs + PBD tet volume "
      "constraints",
      &read_pbd_viscoelastic_settings);
}

PbdViscoelasticModel::PbdViscoelasticModel(const Problem& problem, const PbdViscoelasticSettings& settings)
    : DynamicBaseline(problem, "pbd_viscoelastic", settings.frames), settings_(settings) {
  const Discretization& disc = problem.discretization();
  const Vec3Array& X = disc.rest_positions();
  const Material& mat = disc.material();
  mass_ = disc.masses();
  inv_mass_.resize(mass_.size());
  for (std::size_t i = 0; i < mass_.size(); ++i)
    inv_mass_[i] = problem.constrained()[i] ? 0.0 : 1.0 / mass_[i];
  springs_ = tet_edge_springs(X, disc.tets(), mat.youngs_modulus_pa, 0.0);
  springs_.nonlinearity = settings.nonlinearity;
  for (std::size_t e = 0; e < springs_.size(); ++e) {
    const auto [a, b] = springs_.ends[e];
    springs_.damping[e] = 2.0 * settings.damping_ratio *
                          std::sqrt(springs_.stiffness[e] * mass_[a] * mass_[b] / (mass_[a] + mass_[b]));
  }
  const double k_missing = mat.bulk_modulus() - 2.0 * mat.youngs_modulus_pa / 3.0;
  volume_compliance_per_m3_ = k_missing > 0.0 ? 1.0 / k_missing : 0.0;
  for (const Tet& t : disc.tets()) rest_volume_.push_back(signed_volume(X[t[0]], X[t[1]], X[t[2]], X[t[3]]));
  tet_lambda_.assign(rest_volume_.size(), 0.0);
  double omega2 = 0.0, gamma = 0.0;
  springs_.rate_bounds(mass_, settings.max_strain, omega2, gamma);
  const double dt_max =
      symplectic_euler_step(omega2, gamma + settings.damping_per_s, settings.time_step_safety);
  substeps_ = std::max(1, static_cast<int>(std::ceil(h_ / dt_max - 1e-9)));
  dt_ = h_ / substeps_;
  f_.assign(X.size(), Vec3::Zero());
  x_old_ = X;
  spdlog::info(
      "pbd_viscoelastic: {} springs, {} volume constraints (alpha/V0 = {:.3g} 1/Pa), dt {:.4g} s ({} "
      "substeps per frame)",
      springs_.size(), volume_compliance_per_m3_ > 0.0 ? rest_volume_.size() : 0, volume_compliance_per_m3_,
      dt_, substeps_);
}

void PbdViscoelasticModel::substep(double s, double weight) {
  const Index n = static_cast<Index>(x_.size());
  const auto& fixed = problem_.constrained();
  problem_.external_forces(s, f_ext_);
  std::fill(f_.begin(), f_.end(), Vec3::Zero());
  springs_.add_forces(x_, v_, f_);
  const double decay = std::exp(-settings_.damping_per_s * dt_), inv_dt2 = 1.0 / (dt_ * dt_);
  for (Index i = 0; i < n; ++i) {
    f_int_[i] += weight * f_[i];
    x_old_[i] = x_[i];
    if (fixed[i]) {
      x_[i] = problem_.prescribed_position(i, s);
    } else {
      v_[i] = decay * (v_[i] + (dt_ / mass_[i]) * (f_[i] + f_ext_[i]));
      x_[i] += dt_ * v_[i];
    }
  }
  if (volume_compliance_per_m3_ > 0.0) {
    const auto& tets = problem_.discretization().tets();
    std::fill(tet_lambda_.begin(), tet_lambda_.end(), 0.0);
    constraints::XpbdParameters par;
    par.dt = dt_;
    for (int it = 0; it < settings_.iterations; ++it)
      for (std::size_t t = 0; t < tets.size(); ++t) {
        constraints::TetPositions p;
        std::array<double, 4> w;
        for (int a = 0; a < 4; ++a) p[a] = x_[tets[t][a]], w[a] = inv_mass_[tets[t][a]];
        const auto c = constraints::tet_volume_constraint(p, rest_volume_[t]);
        par.compliance = volume_compliance_per_m3_ * rest_volume_[t];
        std::array<Vec3, 4> dp;
        const double dl = constraints::xpbd_project(c, w, {}, par, tet_lambda_[t], dp);
        for (int a = 0; a < 4; ++a) {
          x_[tets[t][a]] += dp[a];
          f_int_[tets[t][a]] += (weight * dl * inv_dt2) * c.grad[a];
        }
      }
  }
  project_tool_contacts(x_, mass_, dt_, s, weight);
  for (Index i = 0; i < n; ++i)
    if (!fixed[i]) v_[i] = (x_[i] - x_old_[i]) / dt_;
}

StepReport PbdViscoelasticModel::frame(double s_prev, double s_next) {
  std::fill(f_int_.begin(), f_int_.end(), Vec3::Zero());
  reset_loads();
  const double w = 1.0 / substeps_;
  for (int j = 1; j <= substeps_; ++j) substep(s_prev + (s_next - s_prev) * j * w, w);
  StepReport r;
  r.iterations = substeps_;
  return r;
}

nlohmann::json PbdViscoelasticModel::method_info() const {
  return {{"method",
           "nonlinear Kelvin-Voigt springs + XPBD tet volume constraints (interpretation of Xu et al. 2018, "
           "[16])"},
          {"interpretation", true},
          {"springs", springs_.size()},
          {"volume_constraints", volume_compliance_per_m3_ > 0.0 ? rest_volume_.size() : 0},
          {"volume_compliance_per_m3_per_pa", volume_compliance_per_m3_},
          {"nonlinearity", settings_.nonlinearity},
          {"damping_ratio", settings_.damping_ratio},
          {"damping_per_s", settings_.damping_per_s},
          {"iterations", settings_.iterations},
          {"substep_s", dt_},
          {"substeps_per_frame", substeps_},
          {"time_step_safety", settings_.time_step_safety}};
}

}  // namespace vascsim
