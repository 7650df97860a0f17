#include "vascsim/interaction/haptic_loop.hpp"

#include "vascsim/interaction/realtime_thread.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "vascsim/core/error.hpp"

namespace vascsim {

namespace {
void bump(std::atomic<std::uint64_t>& counter) {
  counter.store(counter.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
}
}  // namespace

void to_json(nlohmann::json& json, const HapticStats& s) {
  json = nlohmann::json{{"nominal_rate_hz", s.nominal_rate_hz},
                        {"ticks", s.ticks},
                        {"elapsed_s", s.elapsed_s},
                        {"achieved_rate_hz", s.achieved_rate_hz},
                        {"jitter_p50_ms", s.jitter_p50_ms},
                        {"jitter_p99_ms", s.jitter_p99_ms},
                        {"jitter_max_ms", s.jitter_max_ms},
                        {"late_restarts", s.late_restarts},
                        {"late_restarts_after_startup", s.late_restarts_after_startup},
                        {"contact_updates", s.contact_updates},
                        {"contact_update_rate_hz", s.contact_update_rate_hz},
                        {"force_latency_mean_ms", s.force_latency_mean_ms},
                        {"force_latency_p99_ms", s.force_latency_p99_ms},
                        {"force_latency_max_ms", s.force_latency_max_ms},
                        {"nan_events", s.nan_events},
                        {"clamp_events", s.clamp_events},
                        {"step_limit_events", s.step_limit_events},
                        {"proxy_recoveries", s.proxy_recoveries},
                        {"max_force_sent_n", s.max_force_sent_n},
                        {"scheduling", s.scheduling}};
}

HapticLoop::HapticLoop(Device& device, VirtualCoupling coupling, ForceOutputFilter filter,
                       LatestValue<ContactState>& from_sim, LatestValue<ToolPose>& to_sim,
                       HapticLoopOptions options)
    : device_(device),
      coupling_(std::move(coupling)),
      filter_(std::move(filter)),
      from_sim_(from_sim),
      to_sim_(to_sim),
      options_(options),
      period_s_(1.0 / options.rate_hz) {
  if (!(std::isfinite(options_.rate_hz) && options_.rate_hz > 0.0))
    throw InputError(
        fmt::format("haptic loop: rate_hz = {} must be a positive finite number", options_.rate_hz));
  // The proxy steps by its own fixed h; a different tick would break the stability check it made.
  const double h = coupling_.settings().time_step_s;
  if (std::abs(h - period_s_) > 1e-9 * period_s_)
    throw InputError(fmt::format(
        "haptic loop: the virtual coupling's time_step_s = {} s must equal 1/rate_hz = {} s", h, period_s_));
  if (filter_.settings().max_force_n > device_.limits().max_peak_force_n)
    throw InputError(fmt::format("haptic loop: the force clamp {} N exceeds the {} device's peak force {} N",
                                 filter_.settings().max_force_n, device_.name(),
                                 device_.limits().max_peak_force_n));
}

HapticLoop::~HapticLoop() {
  stop();
}

void HapticLoop::start() {
  if (running()) throw std::logic_error("HapticLoop::start: the loop already runs");
  stop_requested_.store(false, std::memory_order_relaxed);
  thread_ = std::thread([this] { run(); });
  running_.store(true, std::memory_order_release);
}

void HapticLoop::stop() {
  if (!thread_.joinable()) return;
  stop_requested_.store(true, std::memory_order_release);
  thread_.join();
  running_.store(false, std::memory_order_release);
  // Leave the device holding no force.
  filter_.reset();
  device_.send_force(Vec3::Zero(), last_time_s_);
  // The haptic thread only counts; its owner reports.
  const HapticStats s = stats();
  if (s.nan_events > 0)
    spdlog::warn("haptic loop: {} non-finite forces were replaced by zero (of {} ticks)", s.nan_events,
                 s.ticks);
  if (s.proxy_recoveries > 0)
    spdlog::warn("haptic loop: {} ticks had a non-finite contact force or proxy state", s.proxy_recoveries);
  // Behind at the start only (the thread's start, the first frames' page faults) the hand felt one stalled
  // tick before the session settled: information. Behind after it, the machine is too loaded for the loop: a
  // warning.
  if (s.late_restarts_after_startup > 0)
    spdlog::warn(
        "haptic loop: fell behind by more than one period {} times after its first {} ticks (and {} times "
        "before): each time the device kept its force a tick longer; a loaded machine (other processes on "
        "the haptic thread's core) is the usual cause",
        s.late_restarts_after_startup, kStartupTicks, s.late_restarts - s.late_restarts_after_startup);
  else if (s.late_restarts > 0)
    spdlog::info(
        "haptic loop: fell behind by more than one period {} times in its first {} ticks, while the session "
        "started; not after",
        s.late_restarts, kStartupTicks);
}

void HapticLoop::run() {
  if (options_.realtime_priority > 0) {
    const RealtimeSchedulingResult r = request_realtime_scheduling(options_.realtime_priority);
    sched_error_.store(r.error, std::memory_order_relaxed);
    sched_slack_.store(r.timer_slack, std::memory_order_relaxed);
    sched_priority_.store(r.fifo ? r.priority : 0, std::memory_order_release);
  }
  using Clock = std::chrono::steady_clock;
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(period_s_));
  const Clock::time_point start = Clock::now();
  Clock::time_point deadline = start;
  while (!stop_requested_.load(std::memory_order_acquire)) {
    const Clock::time_point now = Clock::now();
    tick(options_.start_time_s + std::chrono::duration<double>(now - start).count());
    // Absolute deadlines: a late tick is followed by an early one, so the mean rate holds. More than a
    // period behind, catching up would be a burst of ticks; restart the schedule instead.
    deadline += period;
    const Clock::time_point after = Clock::now();
    if (after > deadline + period) {
      deadline = after;
      bump(late_restarts_);
      if (ticks_.load(std::memory_order_relaxed) > kStartupTicks) bump(late_restarts_after_startup_);
    }
    std::this_thread::sleep_until(deadline);
  }
}

Vec3 HapticLoop::tick(double time_s) {
  const DevicePose pose = device_.pose(time_s);
  if (from_sim_.update()) bump(contact_updates_);
  const ContactState& contact = from_sim_.value();

  const Vec3 wanted = coupling_.step(pose.position_m, contact);
  proxy_recoveries_.store(coupling_.recoveries(), std::memory_order_relaxed);
  const Vec3 sent = filter_.apply(wanted);
  device_.send_force(sent, time_s);

  ToolPose tool;
  tool.sequence = ++pose_sequence_;
  tool.time_s = time_s;
  tool.set_position(coupling_.proxy_position_m());
  tool.set_orientation(pose.orientation);
  tool.buttons = pose.buttons;
  to_sim_.write(tool);

  if (options_.record != nullptr)
    options_.record->record(pose, sent, coupling_.proxy_position_m(), coupling_.contact_force_n());

  // Statistics.
  const std::uint64_t n = ticks_.load(std::memory_order_relaxed);
  if (n == 0) {
    first_time_s_.store(time_s, std::memory_order_relaxed);
  } else {
    jitter_ms_.add(std::abs(time_s - last_time_s_ - period_s_) * 1e3);
  }
  if (contact.sequence != 0) latency_ms_.add((time_s - contact.tool.time_s) * 1e3);
  last_time_s_ = time_s;
  latest_time_s_.store(time_s, std::memory_order_relaxed);
  ticks_.store(n + 1, std::memory_order_relaxed);
  return sent;
}

HapticStats HapticLoop::stats() const {
  HapticStats s;
  s.nominal_rate_hz = options_.rate_hz;
  s.ticks = ticks_.load(std::memory_order_relaxed);
  s.elapsed_s = s.ticks > 0 ? latest_time_s_.load(std::memory_order_relaxed) -
                                  first_time_s_.load(std::memory_order_relaxed)
                            : 0.0;
  s.contact_updates = contact_updates_.load(std::memory_order_relaxed);
  if (s.elapsed_s > 0.0) {
    s.achieved_rate_hz = static_cast<double>(s.ticks - 1) / s.elapsed_s;
    s.contact_update_rate_hz = static_cast<double>(s.contact_updates) / s.elapsed_s;
  }
  s.jitter_p50_ms = jitter_ms_.quantile(0.5);
  s.jitter_p99_ms = jitter_ms_.quantile(0.99);
  s.jitter_max_ms = jitter_ms_.max();
  s.late_restarts = late_restarts_.load(std::memory_order_relaxed);
  s.late_restarts_after_startup = late_restarts_after_startup_.load(std::memory_order_relaxed);
  s.force_latency_mean_ms = latency_ms_.mean();
  s.force_latency_p99_ms = latency_ms_.quantile(0.99);
  s.force_latency_max_ms = latency_ms_.max();
  s.nan_events = filter_.nan_events();
  s.clamp_events = filter_.clamp_events();
  s.step_limit_events = filter_.step_limit_events();
  s.proxy_recoveries = proxy_recoveries_.load(std::memory_order_relaxed);
  s.max_force_sent_n = filter_.max_force_sent_n();
  s.last_force_sent_n = filter_.last_force_sent_n();
  if (const int priority = sched_priority_.load(std::memory_order_acquire); priority >= 0) {
    RealtimeSchedulingResult r;
    r.fifo = priority > 0;
    r.priority = priority;
    r.error = sched_error_.load(std::memory_order_relaxed);
    r.timer_slack = sched_slack_.load(std::memory_order_relaxed);
    s.scheduling = r.describe();
  }
  return s;
}

void HapticLoop::reset_stats() {
  ticks_.store(0, std::memory_order_relaxed);
  contact_updates_.store(0, std::memory_order_relaxed);
  late_restarts_.store(0, std::memory_order_relaxed);
  late_restarts_after_startup_.store(0, std::memory_order_relaxed);
  first_time_s_.store(0.0, std::memory_order_relaxed);
  latest_time_s_.store(0.0, std::memory_order_relaxed);
  jitter_ms_.clear();
  latency_ms_.clear();
}

}  // namespace vascsim
