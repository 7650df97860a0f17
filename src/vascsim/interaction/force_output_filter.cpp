#include "vascsim/interaction/force_output_filter.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "vascsim/core/error.hpp"

namespace vascsim {

ForceOutputFilter::ForceOutputFilter(const ForceOutputSettings& settings) : settings_(settings) {
  if (!(std::isfinite(settings_.max_force_n) && settings_.max_force_n > 0.0))
    throw InputError(fmt::format("force output filter: max_force_n = {} must be a positive finite number",
                                 settings_.max_force_n));
  if (!(std::isfinite(settings_.max_step_n_per_tick) && settings_.max_step_n_per_tick > 0.0))
    throw InputError(
        fmt::format("force output filter: max_step_n_per_tick = {} must be a positive finite number",
                    settings_.max_step_n_per_tick));
}

ForceOutputFilter ForceOutputFilter::for_device(const DeviceLimits& limits) {
  ForceOutputSettings s;
  s.max_force_n = limits.max_continuous_force_n;
  return ForceOutputFilter(s);
}

ForceOutputFilter::ForceOutputFilter(const ForceOutputFilter& other)
    : settings_(other.settings_),
      previous_(other.previous_),
      nan_events_(other.nan_events()),
      clamp_events_(other.clamp_events()),
      step_events_(other.step_limit_events()),
      max_sent_(other.max_force_sent_n()),
      last_sent_(other.last_force_sent_n()) {}

ForceOutputFilter& ForceOutputFilter::operator=(const ForceOutputFilter& other) {
  settings_ = other.settings_;
  previous_ = other.previous_;
  nan_events_.store(other.nan_events(), std::memory_order_relaxed);
  clamp_events_.store(other.clamp_events(), std::memory_order_relaxed);
  step_events_.store(other.step_limit_events(), std::memory_order_relaxed);
  max_sent_.store(other.max_force_sent_n(), std::memory_order_relaxed);
  last_sent_.store(other.last_force_sent_n(), std::memory_order_relaxed);
  return *this;
}

Vec3 ForceOutputFilter::apply(const Vec3& force_n) {
  if (!force_n.allFinite()) {
    bump(nan_events_);
    previous_.setZero();
    last_sent_.store(0.0, std::memory_order_relaxed);
    return previous_;
  }
  Vec3 f = force_n;
  const double magnitude = f.norm();
  if (magnitude > settings_.max_force_n) {
    f *= settings_.max_force_n / magnitude;
    bump(clamp_events_);
  }
  const Vec3 step = f - previous_;
  const double step_size = step.norm();
  if (step_size > settings_.max_step_n_per_tick) {
    f = previous_ + (settings_.max_step_n_per_tick / step_size) * step;
    bump(step_events_);
  }
  // Rounding in the scalings above can leave |f| an ulp above the clamp; the clamp is a hard limit.
  double sent = f.norm();
  if (sent > settings_.max_force_n) {
    f *= (settings_.max_force_n / sent) * (1.0 - 4.0 * std::numeric_limits<double>::epsilon());
    sent = f.norm();
  }
  previous_ = f;
  last_sent_.store(sent, std::memory_order_relaxed);
  if (sent > max_sent_.load(std::memory_order_relaxed)) max_sent_.store(sent, std::memory_order_relaxed);
  return f;
}

}  // namespace vascsim
