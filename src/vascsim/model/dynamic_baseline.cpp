#include "vascsim/model/dynamic_baseline.hpp"

#include <fmt/format.h>
#include <cmath>

#include "vascsim/core/error.hpp"

namespace vascsim {

BaselineFrames read_baseline_frames(JsonReader& block) {
  BaselineFrames f;
  f.schedule = read_time_schedule(block);
  f.frame_s = block.number("frame_s", 1e-3, 1e-7, 1.0);
  check_step_count(block, f.schedule, f.frame_s, "frame_s");
  return f;
}

ModelEntry baseline_entry(const std::string& name, const std::string& summary,
                          std::function<BaselineFrames(const std::any&)> frames_of) {
  ModelEntry e;
  e.name = name;
  e.summary = summary;
  e.capabilities = {.dynamic = true,
                    .takes_tools = true,
                    .device_driven = true,
                    .releases_regions = false,
                    .quadratic_basis = true};
  e.schedule = [frames_of](const std::any& settings) { return frames_of(settings).schedule; };
  // Every baseline has its own material rule from E and nu (docs/model/25-baselines.md): the scene's law is
  // the point-primitive model's, which they do not use.
  e.law_restriction = [name](const std::any&, const std::string& law) -> std::string {
    if (law == "svk") return "";
    return fmt::format("{} derives its own elasticity from E and nu; material.law '{}' is not used by it",
                       name, law);
  };
  return e;
}

DynamicBaseline::DynamicBaseline(const Problem& problem, std::string name, const BaselineFrames& frames)
    : problem_(problem), name_(std::move(name)), frames_settings_(frames), tools_(problem.tools()) {
  const TimeSchedule& sc = frames.schedule;
  if (!(sc.duration_s > 0.0) || !(sc.output_interval_s > 0.0) || !(frames.frame_s > 0.0))
    throw InputError(fmt::format("{}: duration_s, output_interval_s and frame_s must be > 0", name_));
  // Whole frames per output interval, so output times are exact.
  const double per_output =
      static_cast<double>(whole_steps_per_output(sc, frames.frame_s, name_ + ".frame_s"));
  h_ = sc.output_interval_s / per_output;
  num_steps_ = output_count(sc);
  x_ = problem.discretization().rest_positions();
  v_.assign(x_.size(), Vec3::Zero());
  f_int_.assign(x_.size(), Vec3::Zero());
  loads_.assign(problem.tools().size(), ObstacleLoad{});
}

double DynamicBaseline::load_factor_at(double t) const {
  return ramped_load_factor(t, frames_settings_.schedule.ramp_time_s);
}

void DynamicBaseline::set_tool_pose(std::size_t tool, const Vec3& position_m,
                                    const Eigen::Quaterniond& orientation) {
  tools_.pose(tool, position_m, orientation);
}

double dot(const Vec3Array& a, const Vec3Array& b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += a[i].dot(b[i]);
  return s;
}

void DynamicBaseline::filter_free(Vec3Array& v, const ContactActiveSet& contacts) const {
  for (std::size_t i = 0; i < v.size(); ++i)
    if (problem_.constrained()[i]) v[i].setZero();
  contacts.filter(v);
}

void DynamicBaseline::reset_loads() {
  loads_.assign(problem_.tools().size(), ObstacleLoad{});
}

void DynamicBaseline::project_tool_contacts(Vec3Array& x, const std::vector<double>& mass, double dt,
                                            double s, double weight) {
  const std::size_t no = tools_.size();
  if (no == 0) return;
  std::vector<constraints::Capsule> geometry(no);
  for (std::size_t o = 0; o < no; ++o) geometry[o] = tools_.geometry(o, s);
  const std::vector<Vec3> points = tools_.points(s);
  std::vector<int> count(no, 0);
  const Index n = static_cast<Index>(x.size());
  for (Index i = 0; i < n; ++i) {
    if (problem_.constrained()[i] || !(mass[i] > 0.0)) continue;
    int deepest = -1;
    constraints::ContactConstraint c;
    for (std::size_t o = 0; o < no; ++o) {
      const auto co = obstacle_contact(geometry[o], x[i]);
      if (co.value < 0.0 && (deepest < 0 || co.value < c.value)) c = co, deepest = static_cast<int>(o);
    }
    if (deepest < 0) continue;
    const Vec3 dx = -c.value * c.normal;
    x[i] += dx;
    const Vec3 f = (mass[i] / (dt * dt)) * dx;
    f_int_[i] += weight * f;
    ObstacleLoad& load = loads_[static_cast<std::size_t>(deepest)];
    load.force_vector_n += weight * f;
    load.torque_vector_n_m += weight * (x[i] - points[static_cast<std::size_t>(deepest)]).cross(f);
    ++count[static_cast<std::size_t>(deepest)];
  }
  for (std::size_t o = 0; o < no; ++o) loads_[o].contacts = count[o];
}

StepReport DynamicBaseline::step() {
  const double s_prev = s_;
  const double s_next = load_factor_at(t_ + h_);
  StepReport r = frame(s_prev, s_next);
  t_ += h_;
  s_ = s_next;
  ++frames_;
  iterations_ += r.iterations;
  if (!r.converged) ++unconverged_;
  for (const Vec3& x : x_)
    if (!x.allFinite())
      throw NumericalError(fmt::format("{}: the state became non-finite at t = {:.6g} s", name_, t_));
  r.time_s = t_;
  r.load_factor = s_;
  return r;
}

StepReport DynamicBaseline::advance(int k) {
  const TimeSchedule& sc = frames_settings_.schedule;
  const double t_end = std::min(k * sc.output_interval_s, sc.duration_s);
  StepReport r;
  int iterations = 0;
  bool converged = true;
  while (t_ < t_end - 0.5 * h_) {
    r = step();
    iterations += r.iterations;
    converged = converged && r.converged;
  }
  r.iterations = iterations;
  r.converged = converged;
  r.time_s = t_;
  r.load_factor = s_;
  return r;
}

nlohmann::json DynamicBaseline::info() const {
  nlohmann::json j = method_info();
  j["model"] = name_;
  j["frame_s"] = h_;
  j["frames"] = frames_;
  j["iterations_total"] = iterations_;
  j["unconverged_frames"] = unconverged_;
  j["duration_s"] = frames_settings_.schedule.duration_s;
  j["ramp_time_s"] = frames_settings_.schedule.ramp_time_s;
  j["output_interval_s"] = frames_settings_.schedule.output_interval_s;
  return j;
}

}  // namespace vascsim
