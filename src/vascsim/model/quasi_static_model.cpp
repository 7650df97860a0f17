#include "vascsim/model/quasi_static_model.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <cmath>

#include "vascsim/core/error.hpp"
#include "vascsim/model/inversion_check.hpp"
#include "vascsim/model/tet_stiffness.hpp"

namespace vascsim {

QuasiStaticSettings read_quasi_static_settings(JsonReader& qs) {
  QuasiStaticSettings s;
  s.load_steps = qs.integer("load_steps", 10, 1, 100000);
  s.rel_tolerance = qs.number("rel_tolerance", 1e-8, 1e-14, 0.1);
  s.max_newton_iterations = qs.integer("max_newton_iterations", 60, 1, 10000);
  s.max_cg_iterations = qs.integer("max_cg_iterations", 2000, 1, 1000000);
  s.preconditioner = qs.string("preconditioner", "meshless",
                               {"meshless", "auto", "incomplete_cholesky", "cholesky", "none"});
  s.refactor_cg_iterations = qs.integer("refactor_cg_iterations", 10, 1, 100000);
  s.frame_s = qs.number("frame_s", 1e-3, 1e-6, 10.0);
  qs.finish();
  return s;
}

ModelEntry quasi_static_model_entry() {
  ModelEntry e;
  e.name = "quasi_static";
  e.summary =
      "static equilibrium by Newton-CG at every load step: force-displacement experiments, validation";
  e.capabilities = {.dynamic = false,
                    .takes_tools = true,
                    .device_driven = true,
                    .releases_regions = false,
                    .quadratic_basis = true,
                    .wall_support_default = true,
                    .quadratic_stabilizer_default = true,
                    .accurate_wall_default = true,
                    .embedded_contact = true};
  e.read_settings = [](JsonReader& block) { return std::any(read_quasi_static_settings(block)); };
  e.make = [](const Problem& problem, const std::any& settings) -> std::unique_ptr<Model> {
    return std::make_unique<QuasiStaticModel>(problem, settings_as<QuasiStaticSettings>(settings));
  };
  return e;
}

QuasiStaticModel::QuasiStaticModel(const Problem& problem, const QuasiStaticSettings& settings)
    : problem_(problem),
      settings_(settings),
      x_(problem.discretization().rest_positions()),
      free_(problem),
      contacts_(problem, free_, problem.contact_surface() == nullptr),
      tools_(problem.tools()),
      newton_(problem, free_, contacts_,
              NewtonSettings{settings.rel_tolerance, settings.max_newton_iterations,
                             settings.max_cg_iterations, settings.max_contact_passes}) {
  if (settings.load_steps < 1) throw InputError("quasi_static: load_steps must be >= 1");
  if (!(settings.rel_tolerance > 0.0)) throw InputError("quasi_static: rel_tolerance must be > 0");
  if (!(settings.frame_s > 0.0)) throw InputError("quasi_static: frame_s must be > 0");
  if (problem.num_constrained() == 0)
    throw InputError(
        "key 'regions': quasi_static needs a fixed or displacement region; a static solution needs supports");
  if (const ContactSurface* surface = problem.contact_surface()) {
    embedded_.emplace(*surface, problem.discretization().rest_positions(), problem.tools().size());
    newton_.set_embedded_contact(&*embedded_);
  }
  place_tools(0.0);
  obstacle_load_.assign(problem.tools().size(), ObstacleLoad{});
  if (settings_.preconditioner == "auto")
    settings_.preconditioner = free_.nodes.size() <= 10000 ? "cholesky" : "incomplete_cholesky";
  if (settings_.preconditioner == "meshless") {
    auto factor = std::make_unique<MeshlessFactor>(problem, free_, MeshlessFactorOptions{});
    factor->refactor(x_);
    meshless_ = factor.get();
    preconditioner_ = std::move(factor);
  } else {
    preconditioner_ = std::make_unique<TetStiffnessPreconditioner>(problem, free_, settings_.preconditioner);
  }
  newton_.set_preconditioner(preconditioner_.get());
}

void QuasiStaticModel::place_tools(double s) {
  for (std::size_t o = 0; o < tools_.size(); ++o) {
    if (embedded_)
      embedded_->place(o, tools_.geometry(o, s));
    else
      contacts_.place(o, tools_.geometry(o, s));
  }
}

void QuasiStaticModel::set_tool_pose(std::size_t tool, const Vec3& position_m,
                                     const Eigen::Quaterniond& orientation) {
  tools_.pose(tool, position_m, orientation);
}

StepReport QuasiStaticModel::step() {
  StepReport r = solve(1.0);
  t_ += settings_.frame_s;
  r.time_s = t_;
  return r;
}

void QuasiStaticModel::predict(double s, const Vec3Array& f_ext, StepReport& rep) {
  // From the second load step on: secant extrapolation along the load path (nearly exact for a smooth path,
  // and free). Otherwise the linear one: move the constrained nodes by their increment and the free nodes by
  // the linear response to it, H_ff dx_f = r_f - H_fc dp_c (this avoids crushing the layer next to a driven
  // region).
  const auto& E = problem_.energy();
  const Index n = problem_.discretization().num_nodes();
  const InertiaTerm none;
  Vec3Array dp(n, Vec3::Zero());
  bool moved = false;
  for (Index i = 0; i < n; ++i)
    if (problem_.constrained()[i]) {
      dp[i] = problem_.prescribed_position(i, s) - x_[i];
      moved = moved || dp[i].squaredNorm() > 0.0;
    }
  Vec3Array base = x_;
  for (Index i = 0; i < n; ++i)
    if (problem_.constrained()[i]) base[i] += dp[i];
  // Tools: move them to s; nodes in contact (and nodes the tools now enter) go onto their surfaces, a
  // prescribed normal increment like the one above.
  place_tools(s);
  if (!contacts_.empty()) {
    contacts_.project(base, true);
    for (Index i : free_.nodes)
      if (contacts_.in_contact(i)) {
        dp[i] = base[i] - x_[i];
        moved = moved || dp[i].squaredNorm() > 0.0;
      }
  }
  Vec3Array trial = base;
  if (!x_prev_.empty() && s_ != s_prev_) {
    const double q = (s - s_) / (s_ - s_prev_);
    for (Index i = 0; i < n; ++i)
      if (!problem_.constrained()[i] && !contacts_.in_contact(i)) trial[i] = x_[i] + q * (x_[i] - x_prev_[i]);
    contacts_.project(trial, true);
  } else {
    Vec3Array f_int, r(n), dx, Hd;
    E.forces(x_, f_int, false);
    for (Index i = 0; i < n; ++i) r[i] = f_int[i] + f_ext[i];
    if (moved) {
      E.hessian_product(x_, dp, Hd);
      for (Index i = 0; i < n; ++i) r[i] -= Hd[i];
    }
    rep.inner_iterations += newton_.conjugate_gradients(x_, r, 1e-2, none, dx);
    for (Index i = 0; i < n; ++i)
      if (!problem_.constrained()[i]) trial[i] += dx[i];
    contacts_.project(trial, true);
  }
  x_prev_ = x_;
  s_prev_ = s_;
  x_ = newton_.potential(trial, f_ext, none) <= newton_.potential(base, f_ext, none) ? trial : base;
}

StepReport QuasiStaticModel::solve(double s) {
  StepReport rep;
  rep.load_factor = s;
  Vec3Array f_ext;
  problem_.external_forces(s, f_ext);
  predict(s, f_ext, rep);
  const NewtonResult r = newton_.solve(x_, s, f_ext, InertiaTerm{});
  if (r.loads_measured && embedded_) {
    embedded_->linearize(x_);
    obstacle_load_ = embedded_->loads(tools_.points(s));
  } else if (r.loads_measured && !contacts_.empty()) {
    obstacle_load_ = contacts_.loads(newton_.last_residual(), x_, tools_.points(s));
  }
  rep.iterations = r.iterations;
  rep.inner_iterations += r.cg_iterations;
  rep.converged = r.converged;
  rep.residual = r.residual;
  contact_passes_ += r.contact_passes;
  // The tangent has drifted from the factor's (CG needed many iterations): refactor at this equilibrium, the
  // start of the next load step. Not after the last load step, which nothing follows (on vein-indent that
  // refactorisation was 15 of the run's 92 s).
  const bool nothing_follows = final_load_step_ && s >= 1.0;
  if (meshless_ && !nothing_follows && r.iterations > 0 &&
      r.cg_iterations > settings_.refactor_cg_iterations * r.iterations) {
    meshless_->refactor(x_);
    ++refactorisations_;
  }
  finish_step(s, r.residual, rep);
  return rep;
}

void QuasiStaticModel::finish_step(double s, double res, StepReport& rep) {
  s_ = s;
  total_newton_ += rep.iterations;
  total_cg_ += rep.inner_iterations;
  if (rep.converged) return;
  ++unconverged_steps_;
  const std::string msg = fmt::format(
      "quasi_static: load factor {:.4g} did not converge (relative residual {:.3g} > {:.1g} after {} Newton "
      "iterations)",
      s, res, settings_.rel_tolerance, rep.iterations);
  if (settings_.fail_on_divergence) throw NumericalError(msg);
  spdlog::warn("{}", msg);
}

StepReport QuasiStaticModel::advance(int k) {
  final_load_step_ = k >= settings_.load_steps;
  return solve_without_inversion(s_, static_cast<double>(k) / settings_.load_steps, 0);
}

StepReport QuasiStaticModel::solve_without_inversion(double s_from, double s, int depth) {
  constexpr int kMaxHalvings = 6;  // down to 1/64 of a load step
  // With tools, contact may fold the lattice under a tool's rim at any step size: run/simulation.cpp counts
  // it.
  if (!problem_.tools().empty()) return solve(s);
  const Vec3Array x = x_, x_prev = x_prev_;
  const double s_now = s_, s_prev = s_prev_;
  const int unconverged = unconverged_steps_;
  StepReport rep = solve(s);
  const InversionReport inversion = check_inversion(problem_, x_);
  if (!inversion.any()) return rep;
  if (depth == kMaxHalvings)
    throw NumericalError(
        fmt::format("quasi_static: load factor {:.6g}: {}, even in load steps of 1/{} of the scene's; "
                    "the load inverts the material (too large a displacement or force?)",
                    s, inversion.describe(), 1 << kMaxHalvings));
  spdlog::info("quasi_static: load factor {:.6g}: {}; two half steps instead", s, inversion.describe());
  x_ = x, x_prev_ = x_prev, s_ = s_now, s_prev_ = s_prev, unconverged_steps_ = unconverged;
  const double mid = 0.5 * (s_from + s);
  const StepReport first = solve_without_inversion(s_from, mid, depth + 1);
  StepReport second = solve_without_inversion(mid, s, depth + 1);
  second.iterations += first.iterations + rep.iterations;
  second.inner_iterations += first.inner_iterations + rep.inner_iterations;
  return second;
}

nlohmann::json QuasiStaticModel::info() const {
  return {{"model", "quasi_static"},
          {"load_steps", settings_.load_steps},
          {"rel_tolerance", settings_.rel_tolerance},
          {"preconditioner", preconditioner_->info()},
          {"refactorisations", refactorisations_},
          {"newton_iterations", total_newton_},
          {"cg_iterations", total_cg_},
          {"unconverged_steps", unconverged_steps_},
          {"contact_passes", contact_passes_},
          {"contact", embedded_ ? "embedded" : "nodes"},
          {"frame_s", settings_.frame_s}};
}

}  // namespace vascsim
