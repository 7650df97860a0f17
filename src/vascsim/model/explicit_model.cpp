#include "vascsim/model/explicit_model.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <cmath>

#include "vascsim/core/error.hpp"
#include "vascsim/core/parallel.hpp"
#include "vascsim/model/stability.hpp"

namespace vascsim {

ExplicitSettings read_explicit_settings(JsonReader& ex) {
  ExplicitSettings s;
  const TimeSchedule schedule = read_time_schedule(ex);
  s.duration_s = schedule.duration_s;
  s.ramp_time_s = schedule.ramp_time_s;
  s.output_interval_s = schedule.output_interval_s;
  s.damping_per_s = ex.number("damping_per_s", 10.0, 0.0, 1e6);
  s.dt_s = ex.number("dt_s", 0.0, 0.0, 1.0);
  s.safety = ex.number("safety", 0.5, 0.01, 0.95);
  s.cfl_coefficient = ex.number("cfl_coefficient", 0.4, 0.01, 2.0);
  s.power_iterations = ex.integer("power_iterations", 60, 1, 100000);
  if (s.dt_s > 0.0) check_step_count(ex, schedule, s.dt_s, "dt_s");
  ex.finish();
  return s;
}

ModelEntry explicit_model_entry() {
  ModelEntry e;
  e.name = "explicit";
  e.summary = "symplectic Euler below the stability limit: the verification reference";
  e.capabilities = {.dynamic = true,
                    .takes_tools = false,
                    .device_driven = false,
                    .releases_regions = false,
                    .quadratic_basis = true};
  e.read_settings = [](JsonReader& block) { return std::any(read_explicit_settings(block)); };
  e.make = [](const Problem& problem, const std::any& settings) -> std::unique_ptr<Model> {
    return std::make_unique<ExplicitModel>(problem, settings_as<ExplicitSettings>(settings));
  };
  e.schedule = [](const std::any& settings) {
    const auto& s = settings_as<ExplicitSettings>(settings);
    return TimeSchedule{s.duration_s, s.ramp_time_s, s.output_interval_s};
  };
  return e;
}

ExplicitIntegrator::ExplicitIntegrator(const Problem& problem, double dt_s, double damping_per_s,
                                       bool eq10_literal_sign)
    : problem_(problem),
      dt_(dt_s),
      damping_(damping_per_s),
      literal_sign_(eq10_literal_sign),
      x_(problem.discretization().rest_positions()),
      v_(x_.size(), Vec3::Zero()) {}

void ExplicitIntegrator::substep(double s_next) {
  const auto& m = problem_.discretization().masses();
  const auto& fixed = problem_.constrained();
  last_energy_ = problem_.energy().forces(x_, f_int_);
  problem_.external_forces(s_next, f_ext_);
  const double sign = literal_sign_ ? -1.0 : 1.0;
  const double decay = std::exp(-damping_ * dt_);
  const Index n = static_cast<Index>(x_.size());
#pragma omp parallel for schedule(static) if (n >= kParallelMinNodes)
  for (Index i = 0; i < n; ++i) {
    if (fixed[i]) {
      const Vec3 target = problem_.prescribed_position(i, s_next);
      v_[i] = (target - x_[i]) / dt_;
      x_[i] = target;
      continue;
    }
    v_[i] += dt_ * (f_ext_[i] + sign * f_int_[i]) / m[i];
    v_[i] *= decay;
    x_[i] += dt_ * v_[i];
  }
}

double ExplicitIntegrator::kinetic_energy() const {
  const auto& m = problem_.discretization().masses();
  double k = 0.0;
  for (std::size_t i = 0; i < x_.size(); ++i) k += 0.5 * m[i] * v_[i].squaredNorm();
  return k;
}

ExplicitModel::ExplicitModel(const Problem& problem, const ExplicitSettings& s) : settings_(s) {
  if (!(s.duration_s > 0.0)) throw InputError("explicit: duration_s must be > 0");
  if (!(s.output_interval_s > 0.0)) throw InputError("explicit: output_interval_s must be > 0");
  int iters = 0;
  omega_max_ = max_angular_frequency(problem, problem.discretization().rest_positions(), s.power_iterations,
                                     1e-4, &iters);
  // Power iteration approaches omega_max from below; 5 % margin keeps dt <= safety * dt_crit.
  dt_stability_ = omega_max_ > 0.0 ? 2.0 / (1.05 * omega_max_) : INFINITY;
  dt_cfl_ = cfl_time_step(problem.energy(), s.cfl_coefficient);
  const double dt_auto = std::min(s.safety * dt_stability_, dt_cfl_);
  if (s.dt_s > 0.0) {
    if (s.dt_s > dt_stability_)
      throw InputError(fmt::format(
          "key 'explicit.dt_s': {:.3g} s exceeds the stability limit 2/(1.05 omega_max) = {:.3g} s; "
          "use dt_s <= {:.3g} s or 0 (automatic)",
          s.dt_s, dt_stability_, dt_auto));
    if (s.dt_s > dt_auto)
      spdlog::warn("explicit: dt_s = {:.3g} s is above the safe step {:.3g} s (stability limit {:.3g} s)",
                   s.dt_s, dt_auto, dt_stability_);
    dt_ = s.dt_s;
  } else {
    dt_ = dt_auto;
  }
  // Whole substeps per output interval, so output times are exact.
  const TimeSchedule schedule{s.duration_s, s.ramp_time_s, s.output_interval_s};
  const long long per_output =
      whole_steps_per_output(schedule, dt_, s.dt_s > 0.0 ? "explicit.dt_s" : "explicit.duration_s");
  dt_ = s.output_interval_s / static_cast<double>(per_output);
  num_steps_ = output_count(schedule);
  spdlog::info(
      "explicit: stability limit 2/omega_max = {:.4g} s ({} power iterations), CFL rule {:.4g} s; "
      "substep dt = {:.4g} s, {} substeps per output, {} outputs",
      dt_stability_, iters, dt_cfl_, dt_, per_output, num_steps_);
  integrator_ = std::make_unique<ExplicitIntegrator>(problem, dt_, s.damping_per_s, s.eq10_literal_sign);
}

double ExplicitModel::load_factor_at(double t) const {
  return ramped_load_factor(t, settings_.ramp_time_s);
}

StepReport ExplicitModel::advance(int k) {
  const double t_end = std::min(k * settings_.output_interval_s, settings_.duration_s);
  StepReport r;
  while (t_ < t_end - 0.5 * dt_) {
    t_ += dt_;
    integrator_->substep(load_factor_at(t_));
    ++r.iterations;
  }
  substeps_done_ += r.iterations;
  s_ = load_factor_at(t_);
  for (const auto& x : integrator_->positions())
    if (!x.allFinite())
      throw NumericalError(
          fmt::format("explicit: the state became non-finite at t = {:.6g} s (unstable)", t_));
  r.time_s = t_;
  r.load_factor = s_;
  return r;
}

nlohmann::json ExplicitModel::info() const {
  return {{"model", "explicit"},
          {"dt_s", dt_},
          {"stability_limit_s", dt_stability_},
          {"omega_max_rad_s", omega_max_},
          {"cfl_limit_s", dt_cfl_},
          {"damping_per_s", settings_.damping_per_s},
          {"substeps", substeps_done_},
          {"duration_s", settings_.duration_s},
          {"ramp_time_s", settings_.ramp_time_s},
          {"output_interval_s", settings_.output_interval_s}};
}

}  // namespace vascsim
