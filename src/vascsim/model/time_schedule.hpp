#pragma once
// The time schedule of a dynamic model (explicit, xpbd, paper_literal): how long it runs, how its loads
// ramp in, and how often it reports. The three keys have the same meaning, default and range in each
// model's settings block.

#include <algorithm>

#include "vascsim/core/json_reader.hpp"

namespace vascsim {

struct TimeSchedule {
  double duration_s = 0.02;         ///< simulated time, s
  double ramp_time_s = 0.01;        ///< loads ramp linearly to full over this time, then hold (0: at once), s
  double output_interval_s = 1e-3;  ///< time between output points, s
};

/// Reads duration_s, ramp_time_s and output_interval_s from a model's block, with `defaults` for absent keys.
inline TimeSchedule read_time_schedule(JsonReader& block, const TimeSchedule& defaults = {}) {
  TimeSchedule s;
  s.duration_s = block.number("duration_s", defaults.duration_s, 1e-9, 1e4);
  s.ramp_time_s = block.number("ramp_time_s", defaults.ramp_time_s, 0.0, 1e4);
  s.output_interval_s = block.number("output_interval_s", defaults.output_interval_s, 1e-9, 1e4);
  return s;
}

/// The load factor at time t of a linear ramp over ramp_time_s (1 at once for no ramp).
inline double ramped_load_factor(double t_s, double ramp_time_s) {
  if (ramp_time_s <= 0.0) return 1.0;
  return std::min(t_s / ramp_time_s, 1.0);
}

}  // namespace vascsim
