#include "vascsim/model/tensor_mass_model.hpp"

#include <spdlog/spdlog.h>
#include <algorithm>
#include <cmath>

#include "vascsim/model/tet_stiffness.hpp"

namespace vascsim {

TensorMassSettings read_tensor_mass_settings(JsonReader& b) {
  TensorMassSettings s;
  s.frames = read_baseline_frames(b);
  s.rayleigh_mass_per_s = b.number("rayleigh_mass_per_s", 0.0, 0.0, 1e7);
  s.rayleigh_stiffness_s = b.number("rayleigh_stiffness_s", 1e-4, 0.0, 10.0);
  s.cg_tolerance = b.number("cg_tolerance", 1e-8, 1e-16, 0.5);
  s.max_cg_iterations = b.integer("max_cg_iterations", 500, 1, 1000000);
  b.finish();
  return s;
}

ModelEntry tensor_mass_model_entry() {
  return make_baseline_entry<TensorMassModel, TensorMassSettings>(
      "tensor_mass",
      "baseline [26] Guo et al. 2018: linear tetrahedral tensor-mass, implicit Euler, matrix-free CG",
      &read_tensor_mass_settings);
}

TensorMassModel::TensorMassModel(const Problem& problem, const TensorMassSettings& settings)
    : DynamicBaseline(problem, "tensor_mass", settings.frames),
      settings_(settings),
      free_(problem),
      contacts_(problem, free_) {
  const Discretization& disc = problem.discretization();
  const Material& mat = disc.material();
  K_ = linear_tet_stiffness(disc.rest_positions(), disc.tets(), mat.lame_lambda(), mat.shear_modulus());
  K_.makeCompressed();
  mass_ = disc.masses();
  const double h = h_;
  const Eigen::VectorXd Kdiag = K_.diagonal();
  diag_.resize(3 * mass_.size());
  for (std::size_t d = 0; d < diag_.size(); ++d)
    diag_[d] = (1.0 + h * settings.rayleigh_mass_per_s) * mass_[d / 3] +
               (h * settings.rayleigh_stiffness_s + h * h) * Kdiag[static_cast<Eigen::Index>(d)];
  for (auto* a : {&u_, &f_, &Kv_, &rhs_, &dv_, &r_, &z_, &p_, &Ap_}) a->assign(mass_.size(), Vec3::Zero());
  spdlog::info("tensor_mass: {} vertex and {} edge tensors, frame {:.4g} s", mass_.size(),
               (K_.nonZeros() / 9 - static_cast<long>(mass_.size())) / 2, h_);
}

void TensorMassModel::apply_stiffness(const Vec3Array& in, Vec3Array& out) const {
  const auto n = static_cast<Eigen::Index>(3 * in.size());
  out.resize(in.size());
  Eigen::Map<Eigen::VectorXd>(out[0].data(), n) = K_ * Eigen::Map<const Eigen::VectorXd>(in[0].data(), n);
}

void TensorMassModel::apply_system(const Vec3Array& p, Vec3Array& out) const {
  apply_stiffness(p, out);
  const double a = 1.0 + h_ * settings_.rayleigh_mass_per_s,
               k = h_ * settings_.rayleigh_stiffness_s + h_ * h_;
  for (std::size_t i = 0; i < p.size(); ++i) out[i] = a * mass_[i] * p[i] + k * out[i];
}

int TensorMassModel::solve(const Vec3Array& b, Vec3Array& dv) {
  // Modified PCG (Baraff & Witkin 1998): dv holds the prescribed values of the constrained components; the
  // search stays in the free subspace (prescribed nodes zero, contact normals removed).
  auto filter = [&](Vec3Array& v) { filter_free(v, contacts_); };
  auto precondition = [&](const Vec3Array& r, Vec3Array& z) {
    for (std::size_t i = 0; i < r.size(); ++i)
      for (int c = 0; c < 3; ++c) z[i][c] = r[i][c] / diag_[3 * i + static_cast<std::size_t>(c)];
    filter(z);
  };
  apply_system(dv, Ap_);
  for (std::size_t i = 0; i < b.size(); ++i) r_[i] = b[i] - Ap_[i];
  filter(r_);
  // Relative to the free part of the system: the prescribed rows of b carry the supports' reactions, which
  // would make any residual look small.
  Vec3Array b_free = b;
  filter(b_free);
  const double b_norm = std::max(std::sqrt(dot(b_free, b_free)), std::sqrt(dot(r_, r_)));
  precondition(r_, z_);
  p_ = z_;
  double rz = dot(r_, z_);
  int it = 0;
  while (it < settings_.max_cg_iterations && std::sqrt(dot(r_, r_)) > settings_.cg_tolerance * b_norm) {
    apply_system(p_, Ap_);
    filter(Ap_);
    const double alpha = rz / dot(p_, Ap_);
    for (std::size_t i = 0; i < dv.size(); ++i) dv[i] += alpha * p_[i], r_[i] -= alpha * Ap_[i];
    precondition(r_, z_);
    const double rz_new = dot(r_, z_);
    for (std::size_t i = 0; i < p_.size(); ++i) p_[i] = z_[i] + (rz_new / rz) * p_[i];
    rz = rz_new;
    ++it;
  }
  return it;
}

StepReport TensorMassModel::frame(double /*s_prev*/, double s) {
  const Vec3Array& X = problem_.discretization().rest_positions();
  const std::size_t n = x_.size();
  const double h = h_;
  for (std::size_t o = 0; o < tools_.size(); ++o) contacts_.place(o, tools_.geometry(o, s));
  for (std::size_t i = 0; i < n; ++i) u_[i] = x_[i] - X[i];
  apply_stiffness(u_, f_);
  apply_stiffness(v_, Kv_);
  problem_.external_forces(s, rhs_);
  // b = h (f_ext - K u - (h + beta) K v - alpha M v)
  for (std::size_t i = 0; i < n; ++i)
    rhs_[i] = h * (rhs_[i] - f_[i] - (h + settings_.rayleigh_stiffness_s) * Kv_[i] -
                   settings_.rayleigh_mass_per_s * mass_[i] * v_[i]);
  // Prescribed nodes land on their positions; contacts (the predictor's penetrations) on the tool's surface.
  Vec3Array target(x_);
  for (std::size_t i = 0; i < n; ++i) target[i] = x_[i] + h * v_[i];
  contacts_.project(target, true);
  StepReport rep;
  for (int round = 0; round < 4; ++round) {
    for (std::size_t i = 0; i < n; ++i) {
      if (problem_.constrained()[i])
        dv_[i] = (problem_.prescribed_position(static_cast<Index>(i), s) - x_[i]) / h - v_[i];
      else if (contacts_.in_contact(static_cast<Index>(i))) {
        const Vec3& nrm = contacts_.normal(static_cast<Index>(i));
        dv_[i] = nrm.dot((target[i] - x_[i]) / h - v_[i]) * nrm;
      } else {
        dv_[i].setZero();
      }
    }
    last_cg_ = solve(rhs_, dv_);
    rep.inner_iterations += last_cg_;
    // The contact force is what the unfiltered system lacks: A dv = b + h f_c, so r/h = -f_c per node.
    apply_system(dv_, Ap_);
    for (std::size_t i = 0; i < n; ++i) r_[i] = (rhs_[i] - Ap_[i]) / h;
    if (contacts_.empty() || contacts_.release_pulling(r_) == 0) break;
  }
  cg_total_ += rep.inner_iterations;
  for (std::size_t i = 0; i < n; ++i) {
    v_[i] += dv_[i];
    x_[i] += h * v_[i];
    u_[i] = x_[i] - X[i];
  }
  if (!contacts_.empty()) {
    reset_loads();
    loads_ = contacts_.loads(r_, x_, tools_.points(s));
  }
  apply_stiffness(u_, f_int_);
  for (auto& f : f_int_) f = -f;
  rep.iterations = 1;
  rep.converged = last_cg_ < settings_.max_cg_iterations;
  return rep;
}

nlohmann::json TensorMassModel::method_info() const {
  const Material& m = problem_.discretization().material();
  return {{"method", "linear tetrahedral tensor-mass, implicit Euler, Jacobi-PCG (Guo et al. 2018, [26])"},
          {"lame_lambda_pa", m.lame_lambda()},
          {"shear_modulus_pa", m.shear_modulus()},
          {"rayleigh_mass_per_s", settings_.rayleigh_mass_per_s},
          {"rayleigh_stiffness_s", settings_.rayleigh_stiffness_s},
          {"cg_tolerance", settings_.cg_tolerance},
          {"cg_iterations_total", cg_total_},
          {"cg_iterations_last", last_cg_}};
}

}  // namespace vascsim
