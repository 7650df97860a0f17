#include "vascsim/run/soak.hpp"

#include <unistd.h>

#include <fmt/format.h>
#include <algorithm>
#include <chrono>
#include <fstream>
#include <mutex>
#include <thread>
#include <vector>

#include "vascsim/core/error.hpp"
#include "vascsim/interaction/trajectory.hpp"
#include "vascsim/run/haptic_session.hpp"
#include "vascsim/run/output_writer.hpp"

namespace vascsim {

namespace {

struct MemorySample {
  double time_s, rss_mib;
};

// Samples resident memory every interval on its own thread until destroyed.
class MemorySampler {
 public:
  MemorySampler(double interval_s, std::size_t expected) : start_(std::chrono::steady_clock::now()) {
    samples_.reserve(expected);  // the sampler itself must not grow
    thread_ = std::jthread([this, interval_s](std::stop_token stop) {
      const auto start = start_;
      auto next = start;
      while (!stop.stop_requested()) {
        const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        {
          const std::lock_guard lock(mutex_);
          if (samples_.size() < samples_.capacity()) samples_.push_back({t, resident_memory_mib()});
        }
        next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(
            std::chrono::duration<double>(interval_s));
        while (!stop.stop_requested() && std::chrono::steady_clock::now() < next)
          std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
    });
  }
  /// Seconds since the sampler started (the samples' clock).
  double now_s() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  std::vector<MemorySample> stop() {
    thread_.request_stop();
    thread_.join();
    return samples_;
  }

 private:
  const std::chrono::steady_clock::time_point start_;
  std::mutex mutex_;
  std::vector<MemorySample> samples_;
  std::jthread thread_;
};

// Growth after warm-up (counted from the session's first frame, after the set-up): the last sample against
// the first one after warm-up, the largest excursion, and the least-squares slope (MiB per hour).
nlohmann::json memory_report(const std::vector<MemorySample>& samples, double session_start_s,
                             double session_end_s, double warmup_s) {
  std::vector<MemorySample> after;  // the session's frames after warm-up (not the set-up, not the tear-down)
  for (const auto& s : samples)
    if (s.time_s >= session_start_s + warmup_s && s.time_s <= session_end_s) after.push_back(s);
  nlohmann::json every = nlohmann::json::array();
  for (const auto& s : samples) every.push_back({s.time_s, s.rss_mib});
  nlohmann::json j = {{"samples", samples.size()},
                      {"session_start_s", session_start_s},
                      {"session_end_s", session_end_s},
                      {"warmup_s", warmup_s},
                      {"rss_start_mib", samples.empty() ? 0.0 : samples.front().rss_mib},
                      {"rss_time_s_mib", every}};
  if (after.size() < 2) return j;
  double mean_t = 0.0, mean_m = 0.0, peak = after.front().rss_mib;
  for (const auto& s : after) mean_t += s.time_s, mean_m += s.rss_mib, peak = std::max(peak, s.rss_mib);
  mean_t /= static_cast<double>(after.size());
  mean_m /= static_cast<double>(after.size());
  double stt = 0.0, stm = 0.0;
  for (const auto& s : after)
    stt += (s.time_s - mean_t) * (s.time_s - mean_t), stm += (s.time_s - mean_t) * (s.rss_mib - mean_m);
  j["rss_after_warmup_mib"] = after.front().rss_mib;
  j["rss_end_mib"] = after.back().rss_mib;
  j["rss_peak_after_warmup_mib"] = peak;
  j["growth_after_warmup_mib"] = after.back().rss_mib - after.front().rss_mib;
  j["slope_mib_per_hour"] = stt > 0.0 ? stm / stt * 3600.0 : 0.0;
  return j;
}

std::string soak_markdown(const nlohmann::json& r) {
  const auto& m = r["memory"];
  const auto& j = r["jitter_ms"];
  const auto num = [&](const nlohmann::json& v) {
    return v.is_number() ? fmt::format("{:.4g}", v.get<double>()) : "-";
  };
  std::string md =
      fmt::format("# Soak: {}\n\n| quantity | value |\n|---|---|\n", r["scene"].get<std::string>());
  const auto row = [&](const std::string& k, const std::string& v) {
    md += fmt::format("| {} | {} |\n", k, v);
  };
  row("session (wall clock)",
      fmt::format("{} s, seed {}", num(r["seconds"]), r["seed"].get<std::uint64_t>()));
  row("tool motion",
      fmt::format("depth 0-{} mm along the tool, +-{} mm across, a waypoint every {} s",
                  num(r["bounds"]["depth_m"].get<double>() * 1e3),
                  num(r["bounds"]["lateral_m"].get<double>() * 1e3), num(r["bounds"]["segment_s"])));
  row("ticks", fmt::format("{} at {} Hz", r["ticks"].get<std::uint64_t>(), num(r["achieved_rate_hz"])));
  row("simulation frames",
      fmt::format("{} at {} Hz", r["simulation_steps"].get<std::uint64_t>(), num(r["deformation_rate_hz"])));
  row("NaN events / proxy recoveries", fmt::format("{} / {}", r["nan_events"].get<std::uint64_t>(),
                                                   r["proxy_recoveries"].get<std::uint64_t>()));
  row("clamp events / step-limit events", fmt::format("{} / {}", r["clamp_events"].get<std::uint64_t>(),
                                                      r["step_limit_events"].get<std::uint64_t>()));
  row("late restarts of the haptic schedule", fmt::format("{}", r["late_restarts"].get<std::uint64_t>()));
  row("max force sent / on the tool",
      fmt::format("{} N / {} N", num(r["max_force_sent_n"]), num(r["max_force_on_tool_n"])));
  row("tick jitter p50 / p99 / max",
      fmt::format("{} / {} / {} ms", num(j["p50"]), num(j["p99"]), num(j["max"])));
  row("resident memory after warm-up -> end",
      fmt::format("{} -> {} MiB (warm-up {} s after the set-up)",
                  num(m.value("rss_after_warmup_mib", nlohmann::json())),
                  num(m.value("rss_end_mib", nlohmann::json())), num(m["warmup_s"])));
  row("memory growth after warm-up",
      fmt::format("{} MiB (slope {} MiB/h, peak {} MiB)",
                  num(m.value("growth_after_warmup_mib", nlohmann::json())),
                  num(m.value("slope_mib_per_hour", nlohmann::json())),
                  num(m.value("rss_peak_after_warmup_mib", nlohmann::json()))));
  return md;
}

}  // namespace

double resident_memory_mib() {
  std::ifstream statm("/proc/self/statm");
  double size = 0.0, resident = 0.0;
  if (!(statm >> size >> resident)) return 0.0;
  return resident * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

nlohmann::json run_soak(const Scene& scene, const SoakOptions& options) {
  if (!scene.haptics.enabled)
    throw InputError(
        fmt::format("{}: a soak needs a scene with a 'haptics' block (a real-time scene)", scene.file));
  if (!(options.seconds > 0.0 && options.seconds * scene.haptics.rate_hz <= kMaxSessionTicks))
    throw InputError(fmt::format("soak: --seconds {} must be > 0 and at most {:.0e} ticks at {} Hz",
                                 options.seconds, kMaxSessionTicks, scene.haptics.rate_hz));
  const DevicePose start = read_trajectory(scene.haptics.trajectory).samples().front();
  WanderingDevice device(start, options.bounds);
  Scene soak_scene = scene;
  soak_scene.haptics.duration_s = options.seconds;
  HapticRunOptions session;
  session.out_dir = options.out_dir;
  session.mode = "realtime";
  session.device = &device;
  session.keep_ticks = false;
  MemorySampler sampler(options.rss_interval_s,
                        static_cast<std::size_t>(options.seconds / options.rss_interval_s) + 4096);
  // The first progress call comes with the session's first frame, the last one when its loop ends.
  double session_start_s = -1.0, session_end_s = 0.0;
  session.on_progress = [&](double done, double total) {
    if (session_start_s < 0.0) session_start_s = sampler.now_s();
    session_end_s = sampler.now_s();
    if (options.on_progress) options.on_progress(done, total);
  };
  const nlohmann::json summary = run_haptic_session(soak_scene, session);
  const std::vector<MemorySample> samples = sampler.stop();

  const auto& h = summary["haptics"];
  const auto& loop = h["loop"];
  const double warmup = options.warmup_s >= 0.0 ? options.warmup_s : std::max(10.0, 0.1 * options.seconds);
  const nlohmann::json report = {
      {"scene", scene.name},
      {"scene_file", scene.file},
      {"seconds", options.seconds},
      {"seed", options.bounds.seed},
      {"bounds",
       {{"depth_m", options.bounds.depth_m},
        {"lateral_m", options.bounds.lateral_m},
        {"segment_s", options.bounds.segment_s}}},
      {"interrupted", summary["interrupted"]},
      {"ticks", loop["ticks"]},
      {"achieved_rate_hz", loop["achieved_rate_hz"]},
      {"simulation_steps", h["simulation_steps"]},
      {"deformation_rate_hz", h["deformation_rate_hz"]},
      {"nan_events", loop["nan_events"]},
      {"proxy_recoveries", loop["proxy_recoveries"]},
      {"clamp_events", loop["clamp_events"]},
      {"step_limit_events", loop["step_limit_events"]},
      {"late_restarts", loop["late_restarts"]},
      {"max_force_sent_n", loop["max_force_sent_n"]},
      {"max_force_on_tool_n", h["max_force_on_tool_n"]},
      {"jitter_ms",
       {{"p50", loop["jitter_p50_ms"]}, {"p99", loop["jitter_p99_ms"]}, {"max", loop["jitter_max_ms"]}}},
      {"memory", memory_report(samples, std::max(session_start_s, 0.0), session_end_s, warmup)}};
  const OutputWriter out(options.out_dir);
  out.write_json("soak.json", report);
  out.write_text("soak.md", soak_markdown(report));
  return report;
}

}  // namespace vascsim
