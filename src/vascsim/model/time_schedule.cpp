#include "vascsim/model/time_schedule.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <cmath>

#include "vascsim/core/error.hpp"

namespace vascsim {

namespace {

// The reason a step of step_s cannot be used with this schedule ("" if it can).
std::string step_count_problem(const TimeSchedule& s, double step_s) {
  const double per_output = std::ceil(s.output_interval_s / step_s - 1e-9);
  const double total = per_output * std::ceil(s.duration_s / s.output_interval_s - 1e-9);
  if (!(per_output <= kMaxStepsPerOutput))
    return fmt::format(
        "a step of {:.3g} s gives {:.3g} steps per output interval of {:.3g} s; the limit is {:.0e}", step_s,
        per_output, s.output_interval_s, kMaxStepsPerOutput);
  if (!(total <= kMaxStepsPerRun))
    return fmt::format(
        "a step of {:.3g} s gives {:.3g} steps over duration_s = {:.3g} s; the limit is {:.0e}", step_s,
        total, s.duration_s, kMaxStepsPerRun);
  return "";
}

}  // namespace

TimeSchedule read_time_schedule(JsonReader& block, const TimeSchedule& defaults) {
  TimeSchedule s;
  s.duration_s = block.number("duration_s", defaults.duration_s, 1e-9, 1e4);
  s.ramp_time_s = block.number("ramp_time_s", defaults.ramp_time_s, 0.0, 1e4);
  s.output_interval_s = block.number("output_interval_s", defaults.output_interval_s, 1e-9, 1e4);
  const double outputs = std::ceil(s.duration_s / s.output_interval_s - 1e-9);
  if (outputs > kMaxOutputs)
    block.fail(
        "output_interval_s",
        fmt::format(
            "{:.3g} s gives {:.3g} output points over duration_s = {:.3g} s; at most {:.0e} are allowed",
            s.output_interval_s, outputs, s.duration_s, kMaxOutputs));
  return s;
}

int output_count(const TimeSchedule& s) {
  return std::max(1, static_cast<int>(std::ceil(s.duration_s / s.output_interval_s - 1e-9)));
}

long long whole_steps_per_output(const TimeSchedule& s, double step_s, const std::string& key) {
  const std::string problem = step_count_problem(s, step_s);
  if (!problem.empty()) throw InputError(fmt::format("key '{}': {}", key, problem));
  if (s.output_interval_s < step_s * (1.0 - 1e-9))
    spdlog::warn(
        "key '{}': output_interval_s = {:.3g} s is shorter than the step {:.3g} s, so the step shrinks to "
        "{:.3g} s; set output_interval_s >= the step to keep it",
        key, s.output_interval_s, step_s, s.output_interval_s);
  return static_cast<long long>(std::ceil(s.output_interval_s / step_s - 1e-9));
}

void check_step_count(JsonReader& block, const TimeSchedule& s, double step_s, const std::string& step_key) {
  const std::string problem = step_count_problem(s, step_s);
  if (!problem.empty()) block.fail(step_key, problem);
}

}  // namespace vascsim
