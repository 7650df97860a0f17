#include "vascsim/model/xpbd_model.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "vascsim/constraints/contact_constraint.hpp"
#include "vascsim/constraints/distance_constraint.hpp"
#include "vascsim/constraints/energy_constraint.hpp"
#include "vascsim/constraints/meshless_strain_constraint.hpp"
#include "vascsim/constraints/tet_neo_hookean_constraint.hpp"
#include "vascsim/constraints/xpbd_projection.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/core/parallel.hpp"
#include "vascsim/geometry/boundary.hpp"

namespace vascsim {

namespace {

using constraints::Mat6;
using constraints::Vec6;

template <class Stencils>
Colouring colour(const Stencils& stencils, Index num_nodes) {
  std::vector<Index> start{0}, nodes;
  for (const auto& s : stencils) {
    nodes.insert(nodes.end(), s.begin(), s.end());
    start.push_back(static_cast<Index>(nodes.size()));
  }
  return colour_stencils(start, nodes, num_nodes);
}

}  // namespace

XpbdSettings read_xpbd_settings(JsonReader& xp) {
  XpbdSettings s;
  const TimeSchedule schedule = read_time_schedule(xp);
  s.duration_s = schedule.duration_s;
  s.ramp_time_s = schedule.ramp_time_s;
  s.output_interval_s = schedule.output_interval_s;
  s.step_s = xp.number("step_s", 1e-3, 1e-9, 1.0);
  s.substeps = xp.integer("substeps", XpbdSettings{}.substeps, 1, 10000);
  check_step_count(xp, schedule, s.step_s / s.substeps, "step_s");
  s.iterations = xp.integer("iterations", XpbdSettings{}.iterations, 1, 1000);
  s.damping_per_s = xp.number("damping_per_s", 10.0, 0.0, 1e6);
  s.elastic =
      xp.string("elastic", "meshless_strain", {"meshless_strain", "tet_neo_hookean"}) == "meshless_strain"
          ? XpbdElastic::MeshlessStrain
          : XpbdElastic::TetNeoHookean;
  s.stretch_modulus_pa = xp.number("stretch_modulus_pa", 0.0, 0.0, 1e12);
  s.energy_modulus_pa = xp.number("energy_modulus_pa", 0.0, 0.0, 1e12);
  xp.finish();
  return s;
}

ModelEntry xpbd_model_entry() {
  ModelEntry e;
  e.name = "xpbd";
  e.summary =
      "position-based real-time dynamics of the point-primitive energy (too soft on thin walls at real-time "
      "budgets)";
  e.capabilities = {.dynamic = true,
                    .takes_tools = true,
                    .device_driven = true,
                    .releases_regions = true,
                    .quadratic_basis = false};
  e.read_settings = [](JsonReader& block) { return std::any(read_xpbd_settings(block)); };
  e.make = [](const Problem& problem, const std::any& settings) -> std::unique_ptr<Model> {
    return std::make_unique<XpbdModel>(problem, settings_as<XpbdSettings>(settings));
  };
  e.schedule = [](const std::any& settings) {
    const auto& s = settings_as<XpbdSettings>(settings);
    return TimeSchedule{s.duration_s, s.ramp_time_s, s.output_interval_s};
  };
  e.law_restriction = [](const std::any& settings, const std::string& law) -> std::string {
    if (law == "svk" || settings_as<XpbdSettings>(settings).elastic == XpbdElastic::MeshlessStrain) return "";
    return fmt::format(
        "with xpbd, '{}' needs xpbd.elastic = meshless_strain (the tet option is its own neo-Hookean)", law);
  };
  return e;
}

XpbdModel::XpbdModel(const Problem& problem, const XpbdSettings& s) : problem_(problem), settings_(s) {
  if (!(s.duration_s > 0.0)) throw InputError("xpbd: duration_s must be > 0");
  if (!(s.output_interval_s > 0.0)) throw InputError("xpbd: output_interval_s must be > 0");
  if (!(s.step_s > 0.0)) throw InputError("xpbd: step_s must be > 0");
  if (s.substeps < 1) throw InputError("xpbd: substeps must be >= 1");
  if (s.iterations < 1) throw InputError("xpbd: iterations must be >= 1");
  if (s.damping_per_s < 0.0) throw InputError("xpbd: damping_per_s must be >= 0");
  if (s.stretch_modulus_pa < 0.0 || s.energy_modulus_pa < 0.0)
    throw InputError("xpbd: stretch_modulus_pa and energy_modulus_pa must be >= 0");

  const Discretization& disc = problem.discretization();
  const Index n = disc.num_nodes();
  x_ = disc.rest_positions();
  v_.assign(x_.size(), Vec3::Zero());
  x_prev_ = x_;
  p_ = x_;
  f_constraint_.assign(x_.size(), Vec3::Zero());
  inv_mass_.resize(x_.size());
  for (Index i = 0; i < n; ++i) inv_mass_[i] = problem.constrained()[i] ? 0.0 : 1.0 / disc.masses()[i];
  prescribed_ = problem.constrained();
  released_.assign(problem.regions().size(), 0);
  parallel_ = n >= kParallelMinNodes;

  // Whole steps per output interval, so output times are exact; then n_sub substeps per step.
  const TimeSchedule schedule{s.duration_s, s.ramp_time_s, s.output_interval_s};
  const long long per_output = whole_steps_per_output(schedule, s.step_s, "xpbd.step_s");
  step_ = s.output_interval_s / static_cast<double>(per_output);
  h_ = step_ / s.substeps;
  inv_h2_ = 1.0 / (h_ * h_);
  num_steps_ = output_count(schedule);

  if (s.elastic == XpbdElastic::MeshlessStrain)
    setup_meshless();
  else
    setup_tets();
  const std::size_t no = problem.tools().size();
  contact_lambda_.assign(x_.size() * no, 0.0);
  obstacle_load_.assign(no, ObstacleLoad{});
  obstacle_now_.resize(no);
  tool_now_.resize(no);
  posed_.assign(no, 0);
  pose_from_.resize(no);
  pose_to_.resize(no);
  tool_from_.resize(no);
  tool_to_.resize(no);
  place_obstacles(0.0, 0.0);
  if (s.stretch_modulus_pa > 0.0) setup_edges();
  if (s.energy_modulus_pa > 0.0) setup_barycentre();
  spdlog::info(
      "xpbd: {} elastic constraints in {} colours; step {:.4g} s = {} substeps of {:.4g} s, {} "
      "iteration(s); {} steps per output, {} outputs",
      s.elastic == XpbdElastic::MeshlessStrain ? "meshless strain" : "tet neo-Hookean", num_colours(), step_,
      s.substeps, h_, s.iterations, per_output, num_steps_);
}

void XpbdModel::setup_meshless() {
  const Discretization& disc = problem_.discretization();
  const PointPrimitiveEnergy& energy = problem_.energy();
  if (energy.options().volume_stiffness_pa > 0.0)
    throw InputError(
        "xpbd: the meshless strain constraint does not include the volume term k_v; set "
        "energy.volume_stiffness_pa = 0 or use the explicit/quasi_static model");
  lame_lambda_ = energy.strain_lambda();
  shear_modulus_ = energy.shear_modulus();
  if (!(shear_modulus_ > 0.0 && lame_lambda_ >= 0.0))
    throw InputError(
        fmt::format("xpbd: the meshless strain constraint needs mu > 0 and lambda >= 0 (got lambda = "
                    "{:.4g} Pa, mu = {:.4g} Pa; Poisson ratio must be in [0, 0.5))",
                    lame_lambda_, shear_modulus_));
  // The literal strain eps = F^T F - I = 2E with the same C^ is the constraint 2 Mandel(E).
  strain_scale_ = energy.options().strain == StrainMeasure::MuellerNoHalf ? 2.0 : 1.0;
  stabilise_ = energy.options().stabilizer_alpha > 0.0;
  law_ = energy.options().law.get();
  frames_ = law_ != nullptr && law_->needs_frame() ? &energy.options().frames : nullptr;

  const Index n = disc.num_nodes();
  const PairTable& P = disc.pairs();
  std::vector<Index> start, nodes;
  node_stencils(P, start, nodes);
  update_node_weights();
  node_lambda_.assign(6 * static_cast<std::size_t>(n), 0.0);
  if (stabilise_) pair_lambda_.assign(3 * P.col.size(), 0.0);
  elastic_colours_ = colour_stencils(start, nodes, n);
}

void XpbdModel::update_node_weights() {
  if (settings_.elastic != XpbdElastic::MeshlessStrain) return;
  const Discretization& disc = problem_.discretization();
  const Index n = disc.num_nodes();
  const PairTable& P = disc.pairs();
  weighted_d_.resize(n);
  node_active_.resize(n);
  for (Index i = 0; i < n; ++i) {
    Mat3 D = inv_mass_[i] * disc.self_d()[i] * disc.self_d()[i].transpose();
    bool active = inv_mass_[i] > 0.0;
    for (Index e = P.row_start[i]; e < P.row_start[i + 1]; ++e) {
      D.noalias() += inv_mass_[P.col[e]] * P.d[e] * P.d[e].transpose();
      active = active || inv_mass_[P.col[e]] > 0.0;
    }
    weighted_d_[i] = D;
    node_active_[i] = active ? 1 : 0;
  }
}

void XpbdModel::apply_releases(double t) {
  bool changed = false;
  const auto& regions = problem_.regions();
  for (std::size_t r = 0; r < regions.size(); ++r) {
    if (released_[r] || !(regions[r].release_time_s <= t + 1e-12 * step_)) continue;
    released_[r] = 1;
    changed = true;
    // The nodes keep the velocity of their last prescribed motion (v was updated for all nodes).
    for (Index i : regions[r].nodes) {
      prescribed_[i] = 0;
      inv_mass_[i] = 1.0 / problem_.discretization().masses()[i];
    }
    spdlog::info("xpbd: region '{}' released at t = {:.6g} s", regions[r].name, t);
  }
  if (changed) update_node_weights();
}

void XpbdModel::setup_tets() {
  const Discretization& disc = problem_.discretization();
  // Lame reparametrisation: the linearisation of lambda'/2 (J - 1 - mu/lambda')^2 + mu/2 tr F^T F at F = I
  // is mu |eps|^2 + (lambda' - mu)/2 (tr eps)^2, so lambda' = lambda + mu reproduces linear elasticity
  // (and the P1 tet stiffness, model/tet_stiffness.hpp) at small strain [derived; the XPBD steady state
  // matches the P1 solution, tests/test_xpbd_model.cpp].
  shear_modulus_ = disc.material().shear_modulus();
  lame_lambda_ = disc.material().lame_lambda() + shear_modulus_;
  if (!(disc.material().lame_lambda() > 0.0 && shear_modulus_ > 0.0))
    throw InputError(
        fmt::format("xpbd: the tet neo-Hookean constraints need Lame lambda > 0 and mu > 0 "
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
  tet_lambda_.assign(2 * tets.size(), 0.0);
  if (tet_colours_.num_colours() == 0) tet_colours_ = colour(tets, disc.num_nodes());
  elastic_colours_ = tet_colours_;
  // Shear enters the (C_H, C_D) pair only through the curvature of C_D = |F| (at F = I the two gradients
  // are parallel, so the Gauss-Newton system has no shear stiffness): shear is integrated explicitly and
  // an unloaded body leaves its rest state once h exceeds ~0.6-0.9 Delta_min / c_s (measured on the
  // cantilever, 207 nodes, and the vein, 22914 nodes; tests/test_xpbd_model.cpp). Warn above half of it.
  const double c_s = std::sqrt(shear_modulus_ / disc.material().density_kg_m3);
  h_shear_limit_ = 0.5 * disc.min_spacing() / c_s;
  if (h_ > h_shear_limit_)
    spdlog::warn(
        "xpbd: substep {:.3g} s exceeds the shear stability estimate 0.5 Delta_min / c_s = {:.3g} s "
        "(the tet neo-Hookean pair integrates shear explicitly); use substeps >= {} per {:.3g} s step",
        h_, h_shear_limit_, static_cast<long long>(std::ceil(step_ / h_shear_limit_)), step_);
}

void XpbdModel::setup_edges() {
  const Discretization& disc = problem_.discretization();
  edges_ = tet_edges(disc.tets());
  edge_rest_.resize(edges_.size());
  edge_compliance_.resize(edges_.size());
  for (std::size_t e = 0; e < edges_.size(); ++e) {
    edge_rest_[e] = (x_[edges_[e][0]] - x_[edges_[e][1]]).norm();
    edge_compliance_[e] = 1.0 / (settings_.stretch_modulus_pa * edge_rest_[e]);  // k_e = E_s l0, N/m
  }
  edge_lambda_.assign(edges_.size(), 0.0);
  edge_colours_ = colour(edges_, disc.num_nodes());
}

void XpbdModel::setup_barycentre() {
  const Discretization& disc = problem_.discretization();
  const auto& tets = disc.tets();
  bary_rest_.resize(tets.size());
  bary_compliance_.resize(tets.size());
  const auto springs =
      constraints::barycentre_springs_of_mesh(x_, tets, disc.masses(), settings_.energy_modulus_pa);
  for (std::size_t t = 0; t < tets.size(); ++t) {
    bary_rest_[t] = springs[t].rest_distances;
    bary_compliance_[t] = 1.0 / springs[t].stiffness;
  }
  bary_lambda_.assign(4 * tets.size(), 0.0);
  if (tet_colours_.num_colours() == 0) tet_colours_ = colour(tets, disc.num_nodes());
}

double XpbdModel::load_factor_at(double t) const {
  return ramped_load_factor(t, settings_.ramp_time_s);
}

void XpbdModel::project_node(Index i) {
  if (!node_active_[i]) return;
  const Discretization& disc = problem_.discretization();
  const PairTable& P = disc.pairs();
  const Index begin = P.row_start[i], end = P.row_start[i + 1];
  const Vec3& d_self = disc.self_d()[i];
  // Strain block: c = s Mandel(E), E = 1/2 (F^T F - I), F = sum_j (p_j - p_i) d_ij^T
  // (docs/model/06-gradients.md).
  Mat3 F = Mat3::Zero();
  for (Index e = begin; e < end; ++e) F.noalias() += (p_[P.col[e]] - p_[i]) * P.d[e].transpose();
  Mat3 G;
  if (law_ != nullptr) {
    G = law_energy_correction(i, F);
  } else {
    G = svk_strain_correction(i, F);
  }
  {
    const Vec3 g = G * d_self;
    p_[i] += inv_mass_[i] * g;
    f_constraint_[i] += inv_h2_ * g;
  }
  for (Index e = begin; e < end; ++e) {
    const Index j = P.col[e];
    const Vec3 g = G * P.d[e];
    p_[j] += inv_mass_[j] * g;
    f_constraint_[j] += inv_h2_ * g;
  }
  if (!stabilise_) return;
  project_stabiliser(i, F + G * weighted_d_[i]);
}

Mat3 XpbdModel::law_energy_correction(Index i, const Mat3& F) {
  // Any hyperelastic law (model/materials) as one scalar XPBD energy constraint per node:
  //   C_i = sqrt(2 V_i psi(F_i)),  alpha = 1,  so that 1/2 C_i^2 / alpha = V_i psi(F_i)  (Macklin & Mueller
  //   2021's "energy as a constraint"); grad_k C_i = (V_i / C_i) P(F_i) d_ik, and Delta lambda = -(C + alpha~
  //   lambda) / (sum_k w_k |grad_k C|^2 + alpha~),  alpha~ = 1/h^2, sum_k w_k |G d_k|^2 = tr(G D_i G^T) with
  //   D_i = sum_k w_k d_k d_k^T.
  // At the rest state C = 0 and the gradient direction is undefined: below a tiny energy the node is left
  // alone (its stabiliser still acts).
  const Discretization& disc = problem_.discretization();
  const materials::MaterialFrame* frame =
      frames_ == nullptr ? nullptr : &(*frames_)[static_cast<std::size_t>(i)];
  const double V = disc.volumes()[i];
  const double energy = V * law_->energy_density(F, frame);
  const double floor = 1e-24 * V * shear_modulus_;
  if (!(energy > floor)) return Mat3::Zero();
  const double C = std::sqrt(2.0 * energy);
  const Mat3 Gc = (V / C) * law_->first_piola(F, frame);
  double& lambda = node_lambda_[6 * static_cast<std::size_t>(i)];
  const double denom = (Gc * weighted_d_[i] * Gc.transpose()).trace() + inv_h2_;
  const double dl = (-C - inv_h2_ * lambda) / denom;
  lambda += dl;
  return dl * Gc;
}

Mat3 XpbdModel::svk_strain_correction(Index i, const Mat3& F) {
  const Discretization& disc = problem_.discretization();
  const Mat3 C = F.transpose() * F;
  const Vec6 c = strain_scale_ * constraints::mandel(0.5 * (C - Mat3::Identity()));
  // alpha~ = (V C^)^{-1} / h^2 = (I - beta e e^T) / (2 mu V h^2), beta = lambda / (3 lambda + 2 mu).
  const double a0 = inv_h2_ / (2.0 * shear_modulus_ * disc.volumes()[i]);
  const double beta = lame_lambda_ / (3.0 * lame_lambda_ + 2.0 * shear_modulus_);
  Mat6 A = (strain_scale_ * strain_scale_) * constraints::meshless_strain_block(C, weighted_d_[i]);
  A.diagonal().array() += a0;
  A.topLeftCorner<3, 3>().array() -= a0 * beta;
  Eigen::Map<Vec6> lambda(node_lambda_.data() + 6 * static_cast<std::size_t>(i));
  Vec6 alpha_lambda = a0 * lambda;
  alpha_lambda.head<3>().array() -= a0 * beta * lambda.head<3>().sum();
  const Vec6 dlambda = A.llt().solve(-c - alpha_lambda);
  lambda += dlambda;
  // Delta p_k = w_k J_k^T Delta lambda = w_k G d_k with G = s F L(Delta lambda); force G d_k / h^2.
  return strain_scale_ * F * constraints::unmandel(dlambda);
}

void XpbdModel::project_stabiliser(Index i, const Mat3& F) {
  // Stabiliser (docs/model/09-volume-term-and-stabiliser.md section 9.2): U_i = c_i/2 sum_j w_ij |r_ij|^2,
  // r_ij = p_j - p_i - F_i X_ij. F_i is the weighted least-squares fit of the neighbourhood, so dU_i/dF_i =
  // (sum_j w_ij r_ij X_ij^T) A_i^{-1} = 0 and the gradients with F_i frozen are exact: each pair is a
  // 3-vector constraint with grad_j = I, grad_i = -I and compliance 1/(c_i w_ij). F is the fit after the
  // elastic correction, obtained without a second gather: Delta F = sum_k Delta p_k d_k^T = G D_i.
  const Discretization& disc = problem_.discretization();
  const PairTable& P = disc.pairs();
  const Vec3Array& X = disc.rest_positions();
  const double ci = problem_.energy().stabilizer_coefficients()[i];
  for (Index e = P.row_start[i]; e < P.row_start[i + 1]; ++e) {
    const Index j = P.col[e];
    const double w_sum = inv_mass_[i] + inv_mass_[j];
    if (w_sum == 0.0) continue;
    const Vec3 r = (p_[j] - p_[i]) - F * (X[j] - X[i]);
    const double alpha = inv_h2_ / (ci * P.w[e]);
    Eigen::Map<Vec3> lam(pair_lambda_.data() + 3 * static_cast<std::size_t>(e));
    const Vec3 dl = (-r - alpha * lam) / (w_sum + alpha);
    lam += dl;
    p_[j] += inv_mass_[j] * dl;
    p_[i] -= inv_mass_[i] * dl;
    f_constraint_[j] += inv_h2_ * dl;
    f_constraint_[i] -= inv_h2_ * dl;
  }
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
  const double ah = alpha_h_[t] * inv_h2_, ad = alpha_d_[t] * inv_h2_;
  double hh = 0.0, hd = 0.0, dd = 0.0;
  for (int a = 0; a < 4; ++a) {
    hh += w[a] * ch.grad[a].squaredNorm();
    hd += w[a] * ch.grad[a].dot(cd.grad[a]);
    dd += w[a] * cd.grad[a].squaredNorm();
  }
  double& lh = tet_lambda_[2 * static_cast<std::size_t>(t)];
  double& ld = tet_lambda_[2 * static_cast<std::size_t>(t) + 1];
  const double a11 = hh + ah, a12 = hd, a22 = dd + ad;
  const double det = a11 * a22 - a12 * a12;
  if (!(det > constraints::kDenominatorEpsilon * (a11 * a22 + constraints::kDenominatorEpsilon))) return;
  const double b1 = -ch.value - ah * lh, b2 = -cd.value - ad * ld;
  const double dlh = (a22 * b1 - a12 * b2) / det, dld = (a11 * b2 - a12 * b1) / det;
  lh += dlh;
  ld += dld;
  for (int a = 0; a < 4; ++a) {
    const Vec3 g = dlh * ch.grad[a] + dld * cd.grad[a];
    p_[tet[a]] = x[a] + w[a] * g;
    f_constraint_[tet[a]] += inv_h2_ * g;
  }
}

void XpbdModel::project_edge(Index e) {
  const auto [a, b] = edges_[e];
  const auto c = constraints::distance_constraint(p_[a], p_[b], edge_rest_[e]);
  const std::array<double, 2> w{inv_mass_[a], inv_mass_[b]};
  constraints::XpbdParameters par;
  par.compliance = edge_compliance_[e];
  par.dt = h_;
  std::array<Vec3, 2> dp;
  const double dl = constraints::xpbd_project(c, w, {}, par, edge_lambda_[e], dp);
  p_[a] += dp[0];
  p_[b] += dp[1];
  f_constraint_[a] += (dl * inv_h2_) * c.grad[0];
  f_constraint_[b] += (dl * inv_h2_) * c.grad[1];
}

void XpbdModel::project_barycentre(Index t) {
  const Discretization& disc = problem_.discretization();
  const Tet& tet = disc.tets()[t];
  constraints::TetMasses m;
  std::array<double, 4> w;
  for (int a = 0; a < 4; ++a) {
    m[a] = disc.masses()[tet[a]];
    w[a] = inv_mass_[tet[a]];
  }
  constraints::XpbdParameters par;
  par.compliance = bary_compliance_[t];
  par.dt = h_;
  for (int a = 0; a < 4; ++a) {
    constraints::TetPositions x;
    for (int b = 0; b < 4; ++b) x[b] = p_[tet[b]];
    const auto c = constraints::barycentre_spring_constraint(x, m, a, bary_rest_[t][a]);
    std::array<Vec3, 4> dp;
    const double dl =
        constraints::xpbd_project(c, w, {}, par, bary_lambda_[4 * static_cast<std::size_t>(t) + a], dp);
    for (int b = 0; b < 4; ++b) {
      p_[tet[b]] += dp[b];
      f_constraint_[tet[b]] += (dl * inv_h2_) * c.grad[b];
    }
  }
}

void XpbdModel::place_obstacles(double s, double fraction) {
  const auto& tools = problem_.tools();
  for (std::size_t o = 0; o < tools.size(); ++o) {
    if (!posed_[o]) {
      obstacle_now_[o] = obstacle_at(tools[o], s);
      tool_now_[o] = tool_point_at(tools[o], s);
      continue;
    }
    const auto& from = pose_from_[o];
    const auto& to = pose_to_[o];
    obstacle_now_[o] = {from.a + fraction * (to.a - from.a), from.b + fraction * (to.b - from.b),
                        to.radius_m};
    tool_now_[o] = tool_from_[o] + fraction * (tool_to_[o] - tool_from_[o]);
  }
}

void XpbdModel::set_tool_pose(std::size_t o, const Vec3& position_m, const Eigen::Quaterniond& orientation) {
  const constraints::Capsule g = obstacle_posed(problem_.tools().at(o), position_m, orientation);
  if (!posed_[o]) {
    // The first pose: no sweep from wherever the load factor had the obstacle.
    pose_from_[o] = g;
    tool_from_[o] = position_m;
    posed_[o] = 1;
  }
  pose_to_[o] = g;
  tool_to_[o] = position_m;
}

void XpbdModel::project_contacts() {
  const Index n = static_cast<Index>(x_.size());
  const std::size_t no = problem_.tools().size();
  // One constraint per (node, obstacle), touching one node only: no colouring needed.
#pragma omp parallel for schedule(static) if (parallel_)
  for (Index i = 0; i < n; ++i) {
    if (inv_mass_[i] == 0.0) continue;
    for (std::size_t o = 0; o < no; ++o) {
      const auto c = obstacle_contact(obstacle_now_[o], p_[i]);
      double& lambda = contact_lambda_[static_cast<std::size_t>(i) * no + o];
      if (!c.active && lambda == 0.0) continue;
      // Unilateral, rigid (alpha = 0): Delta lambda = -C / w, clamped so that lambda stays >= 0.
      const double dl = std::max(-c.value / inv_mass_[i], -lambda);
      lambda += dl;
      p_[i] += (inv_mass_[i] * dl) * c.normal;
      f_constraint_[i] += (dl * inv_h2_) * c.normal;
    }
  }
}

template <class Project>
void XpbdModel::sweep(const Colouring& colours, Project&& project) {
  // One parallel region per sweep, a barrier per colour (the implicit one of `omp for`).
#pragma omp parallel if (parallel_)
  for (int c = 0; c < colours.num_colours(); ++c) {
    const Index begin = colours.start[c], end = colours.start[c + 1];
#pragma omp for schedule(static)
    for (Index k = begin; k < end; ++k) project(colours.order[k]);
  }
}

void XpbdModel::substep(double s_next) {
  const Index n = static_cast<Index>(x_.size());
  const auto& m = problem_.discretization().masses();
  const auto& fixed = prescribed_;
  const double h = h_;
  problem_.external_forces(s_next, f_ext_);
#pragma omp parallel for schedule(static) if (parallel_)
  for (Index i = 0; i < n; ++i) {
    x_prev_[i] = x_[i];
    f_constraint_[i].setZero();
    if (fixed[i]) {
      p_[i] = problem_.prescribed_position(i, s_next);
    } else {
      v_[i] += (h / m[i]) * f_ext_[i];
      p_[i] = x_[i] + h * v_[i];
    }
  }
  // Multipliers reset once per substep (XPBD: once per solve, never per iteration).
  for (auto* l : {&node_lambda_, &pair_lambda_, &tet_lambda_, &edge_lambda_, &bary_lambda_, &contact_lambda_})
    std::fill(l->begin(), l->end(), 0.0);
  for (int it = 0; it < settings_.iterations; ++it) {
    if (settings_.elastic == XpbdElastic::MeshlessStrain)
      sweep(elastic_colours_, [this](Index i) { project_node(i); });
    else
      sweep(elastic_colours_, [this](Index t) { project_tet(t); });
    if (!edges_.empty()) sweep(edge_colours_, [this](Index e) { project_edge(e); });
    if (!bary_rest_.empty()) sweep(tet_colours_, [this](Index t) { project_barycentre(t); });
    if (!problem_.tools().empty()) project_contacts();
  }
  if (!problem_.tools().empty()) {
    // The load each obstacle exerted on the tissue: sum lambda n / h^2 with the final normals, and its
    // moment about the tool point (the force acts at the node, which is on the tool's surface).
    const std::size_t no = problem_.tools().size();
    for (std::size_t o = 0; o < no; ++o) {
      ObstacleLoad load;
      for (Index i = 0; i < n; ++i) {
        const double lambda = contact_lambda_[static_cast<std::size_t>(i) * no + o];
        if (lambda == 0.0) continue;
        const Vec3 f = (lambda * inv_h2_) * obstacle_contact(obstacle_now_[o], p_[i]).normal;
        load.force_vector_n += f;
        load.torque_vector_n_m += (p_[i] - tool_now_[o]).cross(f);
        ++load.contacts;
      }
      obstacle_load_[o] = load;
    }
  }
  const double decay = std::exp(-settings_.damping_per_s * h);
#pragma omp parallel for schedule(static) if (parallel_)
  for (Index i = 0; i < n; ++i) {
    v_[i] = (p_[i] - x_prev_[i]) * (decay / h);
    x_[i] = p_[i];
  }
}

StepReport XpbdModel::step() {
  const double t0 = t_;
  for (int j = 1; j <= settings_.substeps; ++j) {
    apply_releases(t0 + (j - 1) * h_);
    const double s_next = load_factor_at(t0 + j * h_);
    place_obstacles(s_next, static_cast<double>(j) / settings_.substeps);
    substep(s_next);
  }
  for (std::size_t o = 0; o < posed_.size(); ++o)
    if (posed_[o]) {
      pose_from_[o] = pose_to_[o];
      tool_from_[o] = tool_to_[o];
    }
  t_ = t0 + step_;
  substeps_done_ += settings_.substeps;
  s_ = load_factor_at(t_);
  for (const auto& x : x_)
    if (!x.allFinite())
      throw NumericalError(fmt::format("xpbd: the state became non-finite at t = {:.6g} s", t_));
  StepReport r;
  r.iterations = settings_.substeps;
  r.time_s = t_;
  r.load_factor = s_;
  return r;
}

StepReport XpbdModel::advance(int k) {
  const double t_end = std::min(k * settings_.output_interval_s, settings_.duration_s);
  StepReport r;
  int substeps = 0;
  while (t_ < t_end - 0.5 * step_) {
    r = step();
    substeps += r.iterations;
  }
  r.iterations = substeps;
  r.time_s = t_;
  r.load_factor = s_;
  return r;
}

nlohmann::json XpbdModel::info() const {
  nlohmann::json j = {
      {"model", "xpbd"},
      {"elastic_constraints",
       settings_.elastic == XpbdElastic::MeshlessStrain ? "meshless_strain" : "tet_neo_hookean"},
      {"step_s", step_},
      {"substep_s", h_},
      {"substeps_per_step", settings_.substeps},
      {"iterations", settings_.iterations},
      {"colours", num_colours()},
      {"damping_per_s", settings_.damping_per_s},
      {"stretch_modulus_pa", settings_.stretch_modulus_pa},
      {"energy_modulus_pa", settings_.energy_modulus_pa},
      {"substeps", substeps_done_},
      {"duration_s", settings_.duration_s},
      {"ramp_time_s", settings_.ramp_time_s},
      {"output_interval_s", settings_.output_interval_s}};
  if (settings_.elastic == XpbdElastic::TetNeoHookean) j["shear_stability_estimate_s"] = h_shear_limit_;
  return j;
}

}  // namespace vascsim
