#pragma once
// The time schedule of a dynamic model (explicit, xpbd, paper_literal): how long it runs, how its loads
// ramp in, and how often it reports. The three keys have the same meaning, default and range in each
// model's settings block.

#include <algorithm>
#include <string>

#include "vascsim/core/json_reader.hpp"

namespace vascsim {

struct TimeSchedule {
  double duration_s = 0.02;         ///< simulated time, s
  double ramp_time_s = 0.01;        ///< loads ramp linearly to full over this time, then hold (0: at once), s
  double output_interval_s = 1e-3;  ///< time between output points, s
};

/// At most this many output points per run (rows of probes.csv, entries of summary.json).
inline constexpr double kMaxOutputs = 1e6;
/// At most this many steps (substeps, frames) per output interval and over the whole run: beyond these a run
/// would not finish in any useful time, and the counts would overflow.
inline constexpr double kMaxStepsPerOutput = 1e9;
inline constexpr double kMaxStepsPerRun = 1e10;

/// Reads duration_s, ramp_time_s and output_interval_s from a model's block, with `defaults` for absent keys.
/// More than kMaxOutputs output points is an InputError at output_interval_s.
TimeSchedule read_time_schedule(JsonReader& block, const TimeSchedule& defaults = {});

/// The number of output points of a schedule (at least 1).
int output_count(const TimeSchedule& s);

/// Whole steps of at most step_s per output interval (so that output times are exact). Throws InputError
/// naming `key` (e.g. "explicit.dt_s") when that is more than kMaxStepsPerOutput per output or
/// kMaxStepsPerRun in all; warns when output_interval_s is shorter than step_s (the step then shrinks to it).
long long whole_steps_per_output(const TimeSchedule& s, double step_s, const std::string& key);

/// The same check at read time: fails at `step_key` of `block`.
void check_step_count(JsonReader& block, const TimeSchedule& s, double step_s, const std::string& step_key);

/// The load factor at time t of a linear ramp over ramp_time_s (1 at once for no ramp).
inline double ramped_load_factor(double t_s, double ramp_time_s) {
  if (ramp_time_s <= 0.0) return 1.0;
  return std::min(t_s / ramp_time_s, 1.0);
}

}  // namespace vascsim
