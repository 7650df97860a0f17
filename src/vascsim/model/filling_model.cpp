#include "vascsim/model/filling_model.hpp"

#include <spdlog/spdlog.h>
#include <cmath>

#include "vascsim/constraints/distance_constraint.hpp"
#include "vascsim/constraints/tet_volume_constraint.hpp"

namespace vascsim {

FillingSettings read_filling_settings(JsonReader& b) {
  FillingSettings s;
  s.frames = read_baseline_frames(b);
  s.substeps = b.integer("substeps", 8, 1, 10000);
  s.iterations = b.integer("iterations", 2, 1, 1000);
  s.damping_per_s = b.number("damping_per_s", 10.0, 0.0, 1e7);
  b.finish();
  return s;
}

ModelEntry filling_model_entry() {
  return make_baseline_entry<FillingModel, FillingSettings>(
      "filling",
      "baseline [27] Ye et al. 2018 (interpretation): particle-filled lattice, XPBD springs + one global "
      "volume "
      "constraint",
      &read_filling_settings);
}

FillingModel::FillingModel(const Problem& problem, const FillingSettings& settings)
    : DynamicBaseline(problem, "filling", settings.frames), settings_(settings) {
  const Discretization& disc = problem.discretization();
  const Material& mat = disc.material();
  mass_ = disc.masses();
  inv_mass_.resize(mass_.size());
  for (std::size_t i = 0; i < mass_.size(); ++i)
    inv_mass_[i] = problem.constrained()[i] ? 0.0 : 1.0 / mass_[i];
  lattice_ = tet_edge_springs(disc.rest_positions(), disc.tets(), mat.youngs_modulus_pa, 0.0);
  spring_lambda_.assign(lattice_.size(), 0.0);
  rest_volume_ = enclosed_volume();
  const double k_missing = mat.bulk_modulus() - 2.0 * mat.youngs_modulus_pa / 3.0;
  volume_compliance_ = k_missing > 0.0 ? rest_volume_ / k_missing : 0.0;
  dt_ = h_ / settings.substeps;
  x_old_ = x_;
  grad_.assign(x_.size(), Vec3::Zero());
  spdlog::info("filling (interpretation): {} lattice springs, enclosed volume {:.4g} m^3, substep {:.4g} s",
               lattice_.size(), rest_volume_, dt_);
}

double FillingModel::enclosed_volume() const {
  double V = 0.0;
  for (const Tet& t : problem_.discretization().tets())
    V += signed_volume(x_[t[0]], x_[t[1]], x_[t[2]], x_[t[3]]);
  return V;
}

void FillingModel::project_volume(double weight) {
  // One scalar constraint over every node: grad_i C = sum of the tet volume gradients around i.
  std::fill(grad_.begin(), grad_.end(), Vec3::Zero());
  double C = -rest_volume_;
  for (const Tet& t : problem_.discretization().tets()) {
    constraints::TetPositions p;
    for (int a = 0; a < 4; ++a) p[a] = x_[t[a]];
    const auto c = constraints::tet_volume_constraint(p, 0.0);
    C += c.value;
    for (int a = 0; a < 4; ++a) grad_[t[a]] += c.grad[a];
  }
  double sum_w = 0.0;
  for (std::size_t i = 0; i < x_.size(); ++i) sum_w += inv_mass_[i] * grad_[i].squaredNorm();
  constraints::XpbdParameters par;
  par.compliance = volume_compliance_;
  par.dt = dt_;
  const double dl = constraints::xpbd_delta_lambda(C, sum_w, 0.0, volume_lambda_, par);
  volume_lambda_ += dl;
  for (std::size_t i = 0; i < x_.size(); ++i) {
    x_[i] += (inv_mass_[i] * dl) * grad_[i];
    f_int_[i] += (weight * dl / (dt_ * dt_)) * grad_[i];
  }
}

void FillingModel::substep(double s, double weight) {
  const Index n = static_cast<Index>(x_.size());
  const auto& fixed = problem_.constrained();
  problem_.external_forces(s, f_ext_);
  for (Index i = 0; i < n; ++i) {
    x_old_[i] = x_[i];
    if (fixed[i]) {
      x_[i] = problem_.prescribed_position(i, s);
    } else {
      v_[i] += (dt_ / mass_[i]) * f_ext_[i];
      x_[i] += dt_ * v_[i];
    }
  }
  std::fill(spring_lambda_.begin(), spring_lambda_.end(), 0.0);
  volume_lambda_ = 0.0;
  constraints::XpbdParameters par;
  par.dt = dt_;
  const double inv_dt2 = 1.0 / (dt_ * dt_);
  for (int it = 0; it < settings_.iterations; ++it) {
    for (std::size_t e = 0; e < lattice_.size(); ++e) {
      const auto [a, b] = lattice_.ends[e];
      const auto c = constraints::distance_constraint(x_[a], x_[b], lattice_.rest_m[e]);
      par.compliance = 1.0 / lattice_.stiffness[e];
      std::array<Vec3, 2> dp;
      const double dl =
          constraints::xpbd_project(c, {inv_mass_[a], inv_mass_[b]}, {}, par, spring_lambda_[e], dp);
      x_[a] += dp[0];
      x_[b] += dp[1];
      f_int_[a] += (weight * dl * inv_dt2) * c.grad[0];
      f_int_[b] += (weight * dl * inv_dt2) * c.grad[1];
    }
    if (volume_compliance_ > 0.0) project_volume(weight);
  }
  project_tool_contacts(x_, mass_, dt_, s, weight);
  const double decay = std::exp(-settings_.damping_per_s * dt_);
  for (Index i = 0; i < n; ++i)
    if (!fixed[i]) v_[i] = (x_[i] - x_old_[i]) * (decay / dt_);
}

StepReport FillingModel::frame(double s_prev, double s_next) {
  std::fill(f_int_.begin(), f_int_.end(), Vec3::Zero());
  reset_loads();
  const double w = 1.0 / settings_.substeps;
  for (int j = 1; j <= settings_.substeps; ++j) substep(s_prev + (s_next - s_prev) * j * w, w);
  StepReport r;
  r.iterations = settings_.substeps;
  return r;
}

nlohmann::json FillingModel::method_info() const {
  return {{"method",
           "particle-filled lattice: XPBD springs + a global volume constraint (interpretation of Ye et al. "
           "2018, [27])"},
          {"interpretation", true},
          {"lattice_springs", lattice_.size()},
          {"rest_volume_m3", rest_volume_},
          {"volume_compliance", volume_compliance_},
          {"substeps_per_frame", settings_.substeps},
          {"substep_s", dt_},
          {"iterations", settings_.iterations},
          {"damping_per_s", settings_.damping_per_s}};
}

}  // namespace vascsim
