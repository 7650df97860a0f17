#include "vascsim/model/xpbd_model.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "vascsim/constraints/tet_neo_hookean_constraint.hpp"
#include "vascsim/constraints/xpbd_projection.hpp"  // kDenominatorEpsilon
#include "vascsim/core/error.hpp"

namespace vascsim {

namespace {

// Parallel loops over the tets of one colour only pay off above this size (as in point_primitive_energy.cpp).
constexpr Index kParallelThreshold = 2048;

// Greedy colouring of tets that share a node (computed once). Returns the tets sorted by colour and the
// start offset of every colour (size = colours + 1).
void colour_tets(const std::vector<Tet>& tets, Index num_nodes, std::vector<Index>& order,
                 std::vector<Index>& start) {
  const Index nt = static_cast<Index>(tets.size());
  // Node -> tets (CSR).
  std::vector<Index> node_start(static_cast<std::size_t>(num_nodes) + 1, 0), node_tets(4 * tets.size());
  for (const Tet& t : tets)
    for (Index n : t) ++node_start[n + 1];
  for (Index i = 0; i < num_nodes; ++i) node_start[i + 1] += node_start[i];
  std::vector<Index> fill(node_start.begin(), node_start.end() - 1);
  for (Index t = 0; t < nt; ++t)
    for (Index n : tets[t]) node_tets[fill[n]++] = t;

  std::vector<int> colour(tets.size(), -1);
  std::vector<Index> stamp;  // stamp[c] == t + 1: colour c is taken by a neighbour of tet t
  int num_colours = 0;
  for (Index t = 0; t < nt; ++t) {
    for (Index n : tets[t])
      for (Index k = node_start[n]; k < node_start[n + 1]; ++k) {
        const int c = colour[node_tets[k]];
        if (c >= 0) stamp[c] = t + 1;
      }
    int c = 0;
    while (c < num_colours && stamp[c] == t + 1) ++c;
    if (c == num_colours) {
      ++num_colours;
      stamp.push_back(0);
    }
    colour[t] = c;
  }
  start.assign(static_cast<std::size_t>(num_colours) + 1, 0);
  for (int c : colour) ++start[c + 1];
  for (int c = 0; c < num_colours; ++c) start[c + 1] += start[c];
  order.resize(tets.size());
  std::vector<Index> pos(start.begin(), start.end() - 1);
  for (Index t = 0; t < nt; ++t) order[pos[colour[t]]++] = t;
}

}  // namespace

XpbdModel::XpbdModel(const Problem& problem, const XpbdSettings& s) : problem_(problem), settings_(s) {
  if (!(s.duration_s > 0.0)) throw InputError("xpbd: duration_s must be > 0");
  if (!(s.output_interval_s > 0.0)) throw InputError("xpbd: output_interval_s must be > 0");
  if (!(s.step_s > 0.0)) throw InputError("xpbd: step_s must be > 0");
  if (s.substeps < 1) throw InputError("xpbd: substeps must be >= 1");
  if (s.iterations < 1) throw InputError("xpbd: iterations must be >= 1");
  if (s.damping_per_s < 0.0) throw InputError("xpbd: damping_per_s must be >= 0");

  const Discretization& disc = problem.discretization();
  const Index n = disc.num_nodes();
  x_ = disc.rest_positions();
  v_.assign(x_.size(), Vec3::Zero());
  x_prev_ = x_;
  p_ = x_;
  inv_mass_.resize(x_.size());
  for (Index i = 0; i < n; ++i) inv_mass_[i] = problem.constrained()[i] ? 0.0 : 1.0 / disc.masses()[i];

  // Lame reparametrisation: the linearisation of lambda'/2 (J - 1 - mu/lambda')^2 + mu/2 tr F^T F at F = I
  // is mu |eps|^2 + (lambda' - mu)/2 (tr eps)^2, so lambda' = lambda + mu reproduces linear elasticity
  // (and the P1 tet stiffness, model/tet_stiffness.hpp) at small strain [derived; the XPBD steady state
  // matches the P1 solution, tests/test_xpbd_model.cpp].
  shear_modulus_ = disc.material().shear_modulus();
  lame_lambda_ = disc.material().lame_lambda() + shear_modulus_;
  if (!(disc.material().lame_lambda() > 0.0 && shear_modulus_ > 0.0))
    throw InputError(fmt::format("xpbd: the tet neo-Hookean constraints need Lame lambda > 0 and mu > 0 "
                                 "(got lambda = {:.4g} Pa, mu = {:.4g} Pa; Poisson ratio must be in (0, 0.5))",
                                 disc.material().lame_lambda(), shear_modulus_));
  const auto& tets = disc.tets();
  if (tets.empty()) throw InputError("xpbd: the discretisation has no virtual tetrahedra");
  dm_inv_.resize(tets.size());
  alpha_h_.resize(tets.size());
  alpha_d_.resize(tets.size());
  for (std::size_t t = 0; t < tets.size(); ++t) {
    constraints::TetPositions X;
    for (int a = 0; a < 4; ++a) X[a] = x_[tets[t][a]];
    const constraints::TetRestShape rest = constraints::tet_rest_shape(X);
    dm_inv_[t] = rest.Dm_inv;
    alpha_h_[t] = constraints::tet_hydrostatic_compliance(lame_lambda_, rest.volume);
    alpha_d_[t] = constraints::tet_deviatoric_compliance(shear_modulus_, rest.volume);
  }
  lambda_.assign(2 * tets.size(), 0.0);
  colour_tets(tets, n, colour_order_, colour_start_);

  // Whole steps per output interval, so output times are exact; then n_sub substeps per step.
  const long long per_output = static_cast<long long>(std::ceil(s.output_interval_s / s.step_s - 1e-9));
  step_ = s.output_interval_s / static_cast<double>(per_output);
  h_ = step_ / s.substeps;
  num_steps_ = static_cast<int>(std::ceil(s.duration_s / s.output_interval_s - 1e-9));
  // Shear enters the (C_H, C_D) pair only through the curvature of C_D = |F| (at F = I the two gradients
  // are parallel, so the Gauss-Newton system has no shear stiffness): shear is integrated explicitly and
  // an unloaded body leaves its rest state once h exceeds ~0.6-0.9 Delta_min / c_s (measured on the
  // cantilever, 207 nodes, and the vein, 22914 nodes; tests/test_xpbd_model.cpp). Warn above half of it.
  const double c_s = std::sqrt(shear_modulus_ / disc.material().density_kg_m3);
  h_shear_limit_ = 0.5 * disc.min_spacing() / c_s;
  spdlog::info("xpbd: {} tets in {} colours; step {:.4g} s = {} substeps of {:.4g} s, {} iteration(s); "
               "{} steps per output, {} outputs",
               tets.size(), num_colours(), step_, s.substeps, h_, s.iterations, per_output, num_steps_);
  if (h_ > h_shear_limit_)
    spdlog::warn("xpbd: substep {:.3g} s exceeds the shear stability estimate 0.5 Delta_min / c_s = {:.3g} s "
                 "(the tet neo-Hookean pair integrates shear explicitly); use substeps >= {} per {:.3g} s step",
                 h_, h_shear_limit_, static_cast<long long>(std::ceil(step_ / h_shear_limit_)), step_);
}

double XpbdModel::load_factor_at(double t) const {
  if (settings_.ramp_time_s <= 0.0) return 1.0;
  return std::min(t / settings_.ramp_time_s, 1.0);
}

void XpbdModel::project_tet(Index t) {
  const Tet& tet = problem_.discretization().tets()[t];
  constraints::TetPositions x;
  std::array<double, 4> w;
  for (int a = 0; a < 4; ++a) {
    x[a] = p_[tet[a]];
    w[a] = inv_mass_[tet[a]];
  }
  if (w[0] + w[1] + w[2] + w[3] == 0.0) return;  // all four nodes prescribed
  // The pair (C_H, C_D) is solved as one coupled 2x2 XPBD system (Macklin & Mueller 2021, section 5,
  // "coupled solve"; Macklin 2016 Eq. 26 in block form without damping):
  //   [sum_k w_k g_ak . g_bk + delta_ab alpha~_a] Delta lambda_b = -C_a - alpha~_a lambda_a,
  //   Delta p_k = w_k (g_Hk Delta lambda_H + g_Dk Delta lambda_D).
  // Projecting them one after the other (Gauss-Seidel) is not rest-stable: at F = I, C_D = sqrt(3) and
  // C_H = -mu/lambda only balance when alpha~ >> sum w|grad C|^2; for h ~ 1e-4..1e-2 s on a mm-cm mesh
  // the deviatoric projection wins and shrinks every tet, so an unloaded body drifts (measured: a
  // 207-node cantilever moved 1 cm at h = 0.1 ms). The coupled solve keeps F = I a fixed point for every h
  // (the gradients are parallel at rest and the alpha~ terms balance exactly).
  const auto ch = constraints::tet_hydrostatic_constraint(x, dm_inv_[t], lame_lambda_, shear_modulus_);
  const auto cd = constraints::tet_deviatoric_constraint(x, dm_inv_[t]);
  const double inv_h2 = 1.0 / (h_ * h_);
  const double ah = alpha_h_[t] * inv_h2, ad = alpha_d_[t] * inv_h2;
  double hh = 0.0, hd = 0.0, dd = 0.0;
  for (int a = 0; a < 4; ++a) {
    hh += w[a] * ch.grad[a].squaredNorm();
    hd += w[a] * ch.grad[a].dot(cd.grad[a]);
    dd += w[a] * cd.grad[a].squaredNorm();
  }
  double& lh = lambda_[2 * static_cast<std::size_t>(t)];
  double& ld = lambda_[2 * static_cast<std::size_t>(t) + 1];
  const double a11 = hh + ah, a12 = hd, a22 = dd + ad;
  const double det = a11 * a22 - a12 * a12;
  if (!(det > constraints::kDenominatorEpsilon * (a11 * a22 + constraints::kDenominatorEpsilon))) return;
  const double b1 = -ch.value - ah * lh, b2 = -cd.value - ad * ld;
  const double dlh = (a22 * b1 - a12 * b2) / det, dld = (a11 * b2 - a12 * b1) / det;
  lh += dlh;
  ld += dld;
  for (int a = 0; a < 4; ++a) p_[tet[a]] = x[a] + w[a] * (dlh * ch.grad[a] + dld * cd.grad[a]);
}

void XpbdModel::substep(double s_next) {
  const Index n = static_cast<Index>(x_.size());
  const auto& m = problem_.discretization().masses();
  const auto& fixed = problem_.constrained();
  const double h = h_;
  problem_.external_forces(s_next, f_ext_);
#pragma omp parallel for schedule(static) if (n >= kParallelThreshold)
  for (Index i = 0; i < n; ++i) {
    x_prev_[i] = x_[i];
    if (fixed[i]) {
      p_[i] = problem_.prescribed_position(i, s_next);
    } else {
      v_[i] += (h / m[i]) * f_ext_[i];
      p_[i] = x_[i] + h * v_[i];
    }
  }
  std::fill(lambda_.begin(), lambda_.end(), 0.0);  // once per substep (XPBD: once per solve)
  const Index num_colours = static_cast<Index>(colour_start_.size()) - 1;
  for (int it = 0; it < settings_.iterations; ++it)
    for (Index c = 0; c < num_colours; ++c) {
      const Index begin = colour_start_[c], end = colour_start_[c + 1];
#pragma omp parallel for schedule(static) if (end - begin >= kParallelThreshold)
      for (Index k = begin; k < end; ++k) project_tet(colour_order_[k]);
    }
  const double decay = std::exp(-settings_.damping_per_s * h);
#pragma omp parallel for schedule(static) if (n >= kParallelThreshold)
  for (Index i = 0; i < n; ++i) {
    v_[i] = (p_[i] - x_prev_[i]) * (decay / h);
    x_[i] = p_[i];
  }
}

StepReport XpbdModel::advance(int k) {
  const double t_end = std::min(k * settings_.output_interval_s, settings_.duration_s);
  StepReport r;
  while (t_ < t_end - 0.5 * step_) {
    const double t0 = t_;
    for (int j = 1; j <= settings_.substeps; ++j) substep(load_factor_at(t0 + j * h_));
    t_ = t0 + step_;
    r.iterations += settings_.substeps;
  }
  substeps_done_ += r.iterations;
  s_ = load_factor_at(t_);
  for (const auto& x : x_)
    if (!x.allFinite())
      throw NumericalError(fmt::format("xpbd: the state became non-finite at t = {:.6g} s", t_));
  r.time_s = t_;
  r.load_factor = s_;
  return r;
}

nlohmann::json XpbdModel::info() const {
  return {{"model", "xpbd"},
          {"elastic_constraints", "tet_neo_hookean"},
          {"step_s", step_},
          {"substep_s", h_},
          {"shear_stability_estimate_s", h_shear_limit_},
          {"substeps_per_step", settings_.substeps},
          {"iterations", settings_.iterations},
          {"colours", num_colours()},
          {"damping_per_s", settings_.damping_per_s},
          {"substeps", substeps_done_},
          {"duration_s", settings_.duration_s},
          {"ramp_time_s", settings_.ramp_time_s},
          {"output_interval_s", settings_.output_interval_s}};
}

}  // namespace vascsim
