#pragma once
// The 1 kHz haptic loop (docs/haptics.md, ARCHITECTURE.md "Threads"). Each tick it reads the device
// pose, takes the newest ContactState from the simulation, steps the VirtualCoupling proxy, passes the
// coupling force through the ForceOutputFilter, sends it, publishes the proxy pose for the
// simulation, and optionally records the tick (SessionRecording).
//
// Two ways to drive it:
//  - start()/stop(): its own std::thread, woken at absolute deadlines (sleep_until on steady_clock). It
//    never waits for the simulation or the renderer: data crosses only through the two LatestValue
//    hand-offs (lock-free) and the atomics behind stats().
//  - tick(time_s): one tick on the caller's thread. The thread calls exactly this, so a recorded
//    session replayed single-threaded through tick() at the recorded times gives the same forces bit
//    for bit (with a deterministic simulation on the same thread).
// After start() a tick allocates nothing, provided the device does not (ScriptedDevice reserves its
// force log) and the recording was reserved for the run (SessionRecording(n)).

#include <algorithm>
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string>
#include <thread>

#include <nlohmann/json_fwd.hpp>

#include "vascsim/interaction/contact_state.hpp"
#include "vascsim/interaction/device.hpp"
#include "vascsim/interaction/force_output_filter.hpp"
#include "vascsim/interaction/latest_value.hpp"
#include "vascsim/interaction/session_recording.hpp"
#include "vascsim/interaction/virtual_coupling.hpp"

namespace vascsim {

struct HapticLoopOptions {
  double rate_hz = 1000.0;
  /// Every tick's pose and sent force is appended here (haptic thread only; read it after stop()).
  /// Reserve it for the run, or record() may allocate in the tick.
  SessionRecording* record = nullptr;
  /// The time passed to the first threaded tick; later ticks add the steady_clock time since start().
  /// For a ScriptedDevice this is where its trajectory starts playing.
  double start_time_s = 0.0;
  /// The thread asks for SCHED_FIFO at this priority (and a 1 us timer slack) when it starts; 0: it does not
  /// ask. Granted or not is in HapticStats::scheduling.
  int realtime_priority = 80;
};

/// A summary of the loop so far; see docs/haptics.md for how to read it. Times from the tick times, so
/// a replay through tick() reproduces them.
/// The ticks a haptic loop counts as its start-up (0.1 s at 1 kHz).
inline constexpr std::uint64_t kStartupTicks = 100;

struct HapticStats {
  double nominal_rate_hz = 0.0;
  std::uint64_t ticks = 0;
  double elapsed_s = 0.0;         ///< last tick time - first tick time
  double achieved_rate_hz = 0.0;  ///< (ticks - 1) / elapsed_s
  /// |tick period - nominal period|, ms: median, 99th percentile (1 us bins), exact maximum.
  double jitter_p50_ms = 0.0, jitter_p99_ms = 0.0, jitter_max_ms = 0.0;
  /// Times the thread fell more than one period behind and skipped ahead instead of bursting.
  std::uint64_t late_restarts = 0;
  /// Of them, those after the first kStartupTicks ticks (the thread's start, its first page faults and the
  /// model's first frames are behind it): these are what a loaded machine costs the hand.
  std::uint64_t late_restarts_after_startup = 0;
  std::uint64_t contact_updates = 0;    ///< new ContactStates taken
  double contact_update_rate_hz = 0.0;  ///< contact_updates / elapsed_s: the deformation rate seen
  /// Age of the contact state used, tick time - ContactState::tool.time_s, ms (ticks with a state only):
  /// mean, 99th percentile (0.1 ms bins), exact maximum.
  double force_latency_mean_ms = 0.0, force_latency_p99_ms = 0.0, force_latency_max_ms = 0.0;
  std::uint64_t nan_events = 0;         ///< non-finite forces replaced by zero
  std::uint64_t clamp_events = 0;       ///< ticks whose force was clamped to the limit
  std::uint64_t step_limit_events = 0;  ///< ticks whose force change was limited
  std::uint64_t proxy_recoveries = 0;   ///< ticks with a non-finite contact force or proxy state
  double max_force_sent_n = 0.0;
  double last_force_sent_n =
      0.0;  ///< the magnitude of the last tick's force (not in to_json: a moment's value)
  /// What the haptic thread got from the scheduler (realtime_thread.hpp); "" before the thread ran.
  std::string scheduling;
};

/// Keys as the field names; for summary.json.
void to_json(nlohmann::json& json, const HapticStats& stats);

/// Counts in fixed bins [0, Bins * width) plus one overflow bin, with the exact maximum and the sum.
/// One thread adds; any thread reads (relaxed atomics: a reader may see a sample counted in one field
/// and not yet in another, which is fine for statistics). No allocation.
template <std::size_t Bins>
class FixedHistogram {
 public:
  explicit FixedHistogram(double bin_width) : width_(bin_width) {}
  void add(double x);
  void clear();
  std::uint64_t count() const { return count_.load(std::memory_order_relaxed); }
  double max() const { return max_.load(std::memory_order_relaxed); }
  double mean() const;
  /// Upper edge of the bin holding the q-quantile; the maximum if that is in the overflow bin.
  double quantile(double q) const;

 private:
  double width_;
  std::array<std::atomic<std::uint32_t>, Bins + 1> bins_{};
  std::atomic<std::uint64_t> count_{0};
  std::atomic<double> max_{0.0}, sum_{0.0};
};

template <std::size_t Bins>
void FixedHistogram<Bins>::add(double x) {
  if (!(x >= 0.0)) x = 0.0;  // negative or NaN: count it in the first bin
  const double position = x / width_;
  const std::size_t bin = position < static_cast<double>(Bins) ? static_cast<std::size_t>(position) : Bins;
  bins_[bin].store(bins_[bin].load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
  count_.store(count_.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
  sum_.store(sum_.load(std::memory_order_relaxed) + x, std::memory_order_relaxed);
  if (x > max_.load(std::memory_order_relaxed)) max_.store(x, std::memory_order_relaxed);
}

template <std::size_t Bins>
void FixedHistogram<Bins>::clear() {
  for (auto& b : bins_) b.store(0, std::memory_order_relaxed);
  count_.store(0, std::memory_order_relaxed);
  max_.store(0.0, std::memory_order_relaxed);
  sum_.store(0.0, std::memory_order_relaxed);
}

template <std::size_t Bins>
double FixedHistogram<Bins>::mean() const {
  const std::uint64_t n = count();
  return n == 0 ? 0.0 : sum_.load(std::memory_order_relaxed) / static_cast<double>(n);
}

template <std::size_t Bins>
double FixedHistogram<Bins>::quantile(double q) const {
  const std::uint64_t n = count();
  if (n == 0) return 0.0;
  // The smallest bin whose cumulative count reaches q n (at least one sample).
  const double target = std::max(1.0, q * static_cast<double>(n));
  std::uint64_t cumulative = 0;
  for (std::size_t i = 0; i < Bins; ++i) {
    cumulative += bins_[i].load(std::memory_order_relaxed);
    if (static_cast<double>(cumulative) >= target)
      return std::min(static_cast<double>(i + 1) * width_, max());
  }
  return max();
}

class HapticLoop {
 public:
  /// Throws InputError if rate_hz is not positive, if the coupling's time step is not 1/rate_hz, or if
  /// the filter's clamp exceeds the device's peak force.
  HapticLoop(Device& device, VirtualCoupling coupling, ForceOutputFilter filter,
             LatestValue<ContactState>& from_sim, LatestValue<ToolPose>& to_sim,
             HapticLoopOptions options = {});
  /// Stops the thread if it runs.
  ~HapticLoop();
  HapticLoop(const HapticLoop&) = delete;
  HapticLoop& operator=(const HapticLoop&) = delete;

  /// Starts the thread. Throws std::logic_error if it already runs.
  void start();
  /// Stops and joins the thread, sends zero force, and logs (spdlog) any NaN or recovery events. Does
  /// nothing if the thread does not run.
  void stop();
  bool running() const { return running_.load(std::memory_order_acquire); }

  /// One tick at `time_s` (deterministic; the thread calls this). Returns the force sent. Only one
  /// thread may tick: never call it while the thread runs.
  Vec3 tick(double time_s);

  /// Safe from any thread, also while the loop runs.
  HapticStats stats() const;
  /// Clears the statistics (not the filter's counters). Not while the thread runs.
  void reset_stats();

  /// The controller and filter; read them only while the thread is stopped.
  const VirtualCoupling& coupling() const { return coupling_; }
  const ForceOutputFilter& filter() const { return filter_; }

 private:
  void run();

  Device& device_;
  VirtualCoupling coupling_;
  ForceOutputFilter filter_;
  LatestValue<ContactState>& from_sim_;
  LatestValue<ToolPose>& to_sim_;
  HapticLoopOptions options_;
  double period_s_;
  std::uint64_t pose_sequence_ = 0;
  double last_time_s_ = 0.0;

  std::thread thread_;
  std::atomic<bool> running_{false}, stop_requested_{false};

  // Statistics: written by the ticking thread only.
  std::atomic<std::uint64_t> ticks_{0}, contact_updates_{0}, late_restarts_{0},
      late_restarts_after_startup_{0};
  std::atomic<std::uint64_t> proxy_recoveries_{0};  // mirrors coupling_.recoveries() for other threads
  std::atomic<double> first_time_s_{0.0}, latest_time_s_{0.0};
  // What the thread got from the scheduler: -1 not asked yet, then SCHED_FIFO priority or 0, and the refusal.
  std::atomic<int> sched_priority_{-1}, sched_error_{0};
  std::atomic<bool> sched_slack_{false};
  FixedHistogram<5000> jitter_ms_{1e-3};  // 1 us bins up to 5 ms
  FixedHistogram<1000> latency_ms_{0.1};  // 0.1 ms bins up to 100 ms
};

}  // namespace vascsim
