#pragma once
// The last stage before the device (docs/haptics.md): every force the haptic loop sends passes here.
//  1. NaN/inf guard: a force with a non-finite component is never sent; zero is sent instead, at once
//     (not ramped: safety first) and the event is counted.
//  2. Clamp: the magnitude is scaled down to max_force_n (the device's continuous limit by default).
//  3. Step limit: the change from the previously sent force is at most max_step_n_per_tick, so a jump
//     (a new simulation state, a recovered proxy) becomes a short ramp. Both the previous and the new
//     force lie inside the clamp ball, and so does the limited force between them.
// The counters are atomics (relaxed; written only by the haptic thread), so another thread can read
// them while the loop runs. The filter never logs or allocates: the thread that owns the loop logs
// the counts (HapticLoop::stop()).

#include <atomic>
#include <cstdint>

#include "vascsim/core/types.hpp"
#include "vascsim/interaction/device.hpp"

namespace vascsim {

struct ForceOutputSettings {
  /// Magnitude clamp. The Omni's continuous limit (DeviceLimits::max_continuous_force_n); a force the
  /// device can hold indefinitely without its motors overheating.
  double max_force_n = 0.88;
  /// Largest change of the sent force per tick (0.1 N per ms = 100 N/s). A hand at 0.1 m/s against the
  /// Omni's full 1 N/mm renderable stiffness changes the force at 100 N/s, so anything the device can
  /// render as a spring passes; only discontinuities are ramped (0 to 0.88 N in 9 ticks).
  double max_step_n_per_tick = 0.1;
};

class ForceOutputFilter {
 public:
  /// Throws InputError unless both settings are positive and finite.
  explicit ForceOutputFilter(const ForceOutputSettings& settings = {});
  /// The default settings with the clamp at the device's continuous limit.
  static ForceOutputFilter for_device(const DeviceLimits& limits);

  // Copies take the counters' current values (the atomics themselves are not copyable).
  ForceOutputFilter(const ForceOutputFilter& other);
  ForceOutputFilter& operator=(const ForceOutputFilter& other);

  /// The force to send for the requested `force_n`. Allocation-free, never throws.
  Vec3 apply(const Vec3& force_n);
  /// Forgets the previous force (the next step starts from zero); keeps the counters.
  void reset() { previous_.setZero(); }

  const ForceOutputSettings& settings() const { return settings_; }
  const Vec3& previous_force_n() const { return previous_; }

  // Safe from any thread.
  std::uint64_t nan_events() const { return nan_events_.load(std::memory_order_relaxed); }
  std::uint64_t clamp_events() const { return clamp_events_.load(std::memory_order_relaxed); }
  std::uint64_t step_limit_events() const { return step_events_.load(std::memory_order_relaxed); }
  /// The largest magnitude sent so far.
  double max_force_sent_n() const { return max_sent_.load(std::memory_order_relaxed); }
  /// The magnitude of the last force sent (0 before the first).
  double last_force_sent_n() const { return last_sent_.load(std::memory_order_relaxed); }

 private:
  // Single writer: a relaxed load and store is enough (and cheaper than a locked read-modify-write).
  static void bump(std::atomic<std::uint64_t>& counter) {
    counter.store(counter.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
  }

  ForceOutputSettings settings_;
  Vec3 previous_ = Vec3::Zero();
  std::atomic<std::uint64_t> nan_events_{0}, clamp_events_{0}, step_events_{0};
  std::atomic<double> max_sent_{0.0}, last_sent_{0.0};
};

}  // namespace vascsim
