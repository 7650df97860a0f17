#include "vascsim/run/haptic_session.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <algorithm>
#include <cmath>
#include <optional>
#include <thread>

#include "vascsim/core/error.hpp"
#include "vascsim/core/interrupt.hpp"
#include "vascsim/core/statistics.hpp"
#include "vascsim/core/stopwatch.hpp"
#include "vascsim/interaction/session_recording.hpp"
#include "vascsim/model/registry.hpp"
#include "vascsim/run/haptic_rig.hpp"
#include "vascsim/run/haptic_session_setup.hpp"
#include "vascsim/run/output_writer.hpp"
#include "vascsim/run/realtime_pacing.hpp"
#include "vascsim/run/runner.hpp"
#include "vascsim/run/tool_reach.hpp"
#include "vascsim/run/tool_series.hpp"

namespace vascsim {

namespace {

// Calls on_progress about every 2 % of the session.
class ProgressThrottle {
 public:
  ProgressThrottle(const HapticRunOptions& options, double duration)
      : options_(options), duration_(duration) {}
  void operator()(double done) {
    if (options_.on_progress && done - last_ >= 0.02 * duration_) {
      options_.on_progress(done, duration_);
      last_ = done;
    }
  }

 private:
  const HapticRunOptions& options_;
  double duration_, last_ = -1.0;
};

// The frames of a session: every one, or (keep_ticks false: soaks) the newest kRecentFrames in a ring, so
// that memory stays constant however long the session runs; the count and the largest force cover all of
// them.
class FrameLog {
 public:
  static constexpr std::size_t kRecentFrames = 1 << 16;
  FrameLog(bool keep_all, std::size_t expected) : keep_all_(keep_all) {
    frames_.reserve(keep_all ? expected : kRecentFrames);
  }
  void add(const FrameSample& s) {
    max_force_n_ = std::max(max_force_n_, s.force_n.norm());
    touched_ = touched_ || s.contacts > 0 || s.force_n.norm() > 0.0;
    if (!s.converged) ++unconverged_;
    if (keep_all_ || frames_.size() < kRecentFrames)
      frames_.push_back(s);
    else
      frames_[count_ % kRecentFrames] = s;
    ++count_;
  }
  /// Every frame in order, or the newest kRecentFrames (in ring order).
  const std::vector<FrameSample>& frames() const { return frames_; }
  std::size_t count() const { return count_; }
  double max_force_n() const { return max_force_n_; }
  /// Frames that did not converge, of all of them.
  std::size_t unconverged() const { return unconverged_; }
  /// Whether any frame had a contact or a force on the tool.
  bool touched() const { return touched_; }

 private:
  bool keep_all_;
  std::vector<FrameSample> frames_;
  std::size_t count_ = 0;
  double max_force_n_ = 0.0;
  std::size_t unconverged_ = 0;
  bool touched_ = false;
};

// Lockstep: one thread; the loop ticks at the nominal times and the model steps every ticks_per_step ticks
// with the pose of that tick. Deterministic. Returns false when interrupted (at a frame boundary).
bool run_lockstep(const Scene& scene, std::size_t n_ticks, HapticRig& rig, FrameLog& history,
                  const std::function<void()>& after_frame, ProgressThrottle& progress) {
  const double period = 1.0 / scene.haptics.rate_hz;
  const auto per_frame = static_cast<std::size_t>(scene.haptics.ticks_per_step);
  for (std::size_t k = 0; k < n_ticks; k += per_frame) {
    if (interrupt_requested()) return false;
    history.add(rig.lockstep_frame(k));
    after_frame();
    progress(static_cast<double>(k) * period);
  }
  rig.tick_through(n_ticks - 1);
  return true;
}

// Realtime: the haptic loop on its own thread at wall-clock rate, the model on this thread as fast as it can
// (never ahead of the wall clock); only the two LatestValue hand-offs are shared. Returns false when
// interrupted.
bool run_realtime(const SessionInputs& in, HapticRig& rig, DeviceDrivenModel& model, FrameLog& history,
                  const std::function<void()>& after_frame, ProgressThrottle& progress) {
  const DeformationThreads threads;
  rig.start();
  try {
    const RealtimeClock clock;
    FrameSample sample;
    while (clock.seconds() < in.duration_s && !interrupt_requested()) {
      if (!rig.realtime_frame(sample)) {
        std::this_thread::sleep_for(std::chrono::microseconds(100));
        continue;
      }
      history.add(sample);
      after_frame();
      progress(clock.seconds());
      clock.wait_for(model.time());
    }
  } catch (...) {
    rig.stop();
    throw;
  }
  rig.stop();
  return !interrupt_requested();
}

std::string history_row(const FrameSample& s) {
  return fmt::format(
      "{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},"
      "{:.17g},{},{:.3g},{},{:.17g},{:.17g},{:.17g},{:.6g},{:.4f}",
      s.sim_time_s, s.pose_time_s, s.tool_position_m.x(), s.tool_position_m.y(), s.tool_position_m.z(),
      s.force_n.x(), s.force_n.y(), s.force_n.z(), s.force_n.norm(), s.torque_n_m.x(), s.torque_n_m.y(),
      s.torque_n_m.z(), s.contacts, s.residual, s.converged ? 1 : 0, s.pose_position_m.x(),
      s.pose_position_m.y(), s.pose_position_m.z(), s.tool_lag_m, s.wall_s * 1e3);
}

// The replay against the recording it plays: bit-identical in lockstep on one thread.
nlohmann::json replay_comparison(const HapticRunOptions& options, const SessionRecording& recording,
                                 const std::vector<ForceSample>& recorded) {
  const auto& ticks = recording.ticks();
  const std::size_t n = std::min(ticks.size(), recorded.size());
  double largest = 0.0;
  bool identical = ticks.size() == recorded.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 d = ticks[i].force_n - recorded[i].force_n;
    largest = std::max(largest, d.cwiseAbs().maxCoeff());
    identical = identical && d.isZero(0.0) && ticks[i].pose.time_s == recorded[i].time_s;
  }
  return {{"file", options.replay.string()},
          {"ticks_compared", n},
          {"max_force_difference_n", largest},
          {"bit_identical", identical}};
}

nlohmann::json session_statistics(const Scene& scene, const HapticRunOptions& options,
                                  const SessionInputs& in, const HapticRig& rig, const FrameLog& history,
                                  double run_s) {
  std::vector<double> step_ms;
  double max_lag_m = 0.0;  // how far the model's tool stayed behind the device pose its frame started from
  for (const auto& s : history.frames()) {
    step_ms.push_back(s.wall_s * 1e3);
    max_lag_m = std::max(max_lag_m, s.tool_lag_m);
  }
  const double max_force = history.max_force_n();
  const HapticsSpec& spec = scene.haptics;
  nlohmann::json haptics = {
      {"mode", in.mode},
      {"tool", scene.obstacles[in.tool].name},
      {"device", std::string(rig.device().name())},
      {"trajectory", options.replay.empty() ? spec.trajectory : options.replay.string()},
      {"duration_s", in.duration_s},
      {"rate_hz", spec.rate_hz},
      {"ticks", rig.loop().stats().ticks},
      {"simulation_steps", history.count()},
      {"deformation_rate_hz", run_s > 0.0 ? static_cast<double>(history.count()) / run_s : 0.0},
      {"step_wall_ms",
       {{"p50", quantile(step_ms, 0.5)},
        {"p99", quantile(step_ms, 0.99)},
        {"max", step_ms.empty() ? 0.0 : *std::max_element(step_ms.begin(), step_ms.end())}}},
      {"max_force_on_tool_n", max_force},
      {"max_tool_lag_m", max_lag_m},
      {"force_scale", spec.force_scale},
      {"force_limit_n", spec.force_limit_n},
      {"loop", rig.loop().stats()}};
  if (!options.replay.empty())
    haptics["replay"] = replay_comparison(options, rig.recording(), in.recorded_forces);
  return haptics;
}

// force_history.csv, session.csv, haptic_ticks.csv and the --record file (sessions that keep their ticks).
void write_session_files(const OutputWriter& out, const HapticRunOptions& options, const HapticRig& rig,
                         const FrameLog& history) {
  CsvTable history_csv = out.table("force_history.csv", force_history_columns());
  for (const auto& s : history.frames()) history_csv.add_row(history_row(s));
  rig.recording().write_csv(out.path("session.csv"));
  rig.recording().write_ticks_csv(out.path("haptic_ticks.csv"));
  if (!options.record.empty()) rig.recording().write_csv(options.record);
}

// What the finished session found suspicious, one line each: a tool whose frames never handed on a contact
// force, either because its path never reached the tissue or because no frame in contact got far enough to
// hand its force on (implicit.handoff_max_residual: frames too slow for the hand, on a loaded machine or at a
// fast hand). `path_reaches_tissue` is unknown (nullopt) for a device of the caller's (a soak's wandering
// one).
std::vector<std::string> session_warnings(const Scene& scene, const SessionInputs& in,
                                          const FrameLog& history, std::optional<bool> path_reaches_tissue) {
  if (history.touched() || history.count() == 0) return {};
  const std::string& name = scene.obstacles[in.tool].name;
  const std::string advice =
      "the hand got no force of the tissue, only the coupling's. The frames are too slow for this hand (a "
      "loaded machine, or a hand faster than the model follows): see the frames' residuals in "
      "force_history.csv, run the session in lockstep (haptics.mode = \"lockstep\") or on a less loaded "
      "machine";
  if (path_reaches_tissue.value_or(true) && history.unconverged() > 0)
    return {
        fmt::format("the tool '{}' {}none of the {} frames handed on a contact force ({} ended before "
                    "converging): {}",
                    name, path_reaches_tissue ? "reached the tissue, but " : "was driven by the device, and ",
                    history.count(), history.unconverged(), advice)};
  // A trajectory of the scene's own can be checked; a device of the caller's cannot.
  return {fmt::format(
      "the tool '{}' never touched the tissue (no contact and zero force in all {} frames){}", name,
      history.count(),
      path_reaches_tissue ? ": check the positions of the trajectory (haptics.device.trajectory, m)" : "")};
}

}  // namespace

std::vector<std::string> force_history_columns() {
  return {"sim_time_s",   "pose_time_s",  "tool_x_m",  "tool_y_m",          "tool_z_m",
          "force_x_n",    "force_y_n",    "force_z_n", "force_magnitude_n", "torque_x_n_m",
          "torque_y_n_m", "torque_z_n_m", "contacts",  "residual",          "converged",
          "pose_x_m",     "pose_y_m",     "pose_z_m",  "tool_lag_m",        "step_wall_ms"};
}

nlohmann::json run_haptic_session(const Scene& scene, const HapticRunOptions& options) {
  const HapticsSpec& spec = scene.haptics;
  const OutputWriter out(options.out_dir);
  const Stopwatch total;
  SessionSetup setup(scene, options);
  const SessionInputs& in = setup.inputs();
  Simulation& sim = setup.simulation();
  DeviceDrivenModel& model = setup.model();
  HapticRig& rig = setup.rig();
  const std::size_t n_ticks = setup.ticks();
  if (options.after_setup) options.after_setup(sim, setup.frames());
  // Where the scene's trajectory drives the tool (not a device of the caller's, such as a soak's).
  std::optional<ToolReach> reach;
  if (options.device == nullptr)
    reach = tool_reach_on_trajectory(scene.obstacles[in.tool], in.trajectory, in.duration_s,
                                     sim.discretization().rest_positions(), true);
  // The scene's own warnings lead summary.json's (`vascsim run` logged them with the model's accuracy
  // warnings).
  std::vector<std::string> warnings = scene.warnings;
  if (reach && !reach->touches()) {
    warnings.push_back(tool_reach_warning(*reach, scene.obstacles[in.tool], in.tool));
    spdlog::warn("{}", warnings.back());
  }
  const double setup_s = total.seconds();

  // Surface series at the model's output interval (every frame for a load-stepped model).
  const ModelEntry& entry = find_model(scene.model);
  const bool surface = scene.output.surface && sim.body().surface.has_value();
  VtkSeries surface_series = out.series("surface");
  ToolSeries tool_series(out, scene, surface);
  const double output_interval =
      entry.schedule ? entry.schedule(scene.own_model_settings()).output_interval_s : model.frame_length_s();
  const long long frames_per_output = std::max(1LL, std::llround(output_interval / model.frame_length_s()));
  long long frames = 0;
  auto write_frame = [&]() {
    if (!surface || frames % (frames_per_output * scene.output.vtk_every) != 0) return;
    surface_series.add_surface(model.time(), fmt::format("surface_{:05d}.vtu", frames), sim.surface_frame(),
                               *sim.body().surface);
    std::vector<constraints::Capsule> tools = tools_at(scene, 0.0);
    const DevicePose start = in.trajectory.at(in.trajectory.start_time_s());
    tools[in.tool] = frames == 0
                         ? obstacle_posed(scene.obstacles[in.tool], start.position_m, start.orientation)
                         : obstacle_posed(scene.obstacles[in.tool], rig.last_pose().position(),
                                          rig.last_pose().orientation());
    tool_series.add(model.time(), fmt::format("tools_{:05d}.vtu", frames), tools);
  };
  auto after_frame = [&]() {
    ++frames;
    // Inverted material ends the session (exit 3), checked at the output interval: O(nodes) per check.
    if (frames % frames_per_output == 0)
      sim.check_state(fmt::format("frame {} (t = {:.6g} s)", frames, model.time()));
    write_frame();
  };

  FrameLog history(options.keep_ticks, n_ticks / static_cast<std::size_t>(spec.ticks_per_step) + 16);
  write_frame();
  ProgressThrottle progress(options, in.duration_s);
  const Stopwatch run;
  const bool completed = in.mode == "lockstep"
                             ? run_lockstep(scene, n_ticks, rig, history, after_frame, progress)
                             : run_realtime(in, rig, model, history, after_frame, progress);
  const double run_s = run.seconds();
  if (options.on_progress) options.on_progress(in.duration_s, in.duration_s);

  if (options.keep_ticks) write_session_files(out, options, rig, history);

  for (const std::string& w :
       session_warnings(scene, in, history, reach ? std::optional<bool>(reach->touches()) : std::nullopt)) {
    spdlog::warn("{}", w);
    warnings.push_back(w);
  }

  nlohmann::json summary = describe_run(scene, sim);
  summary["haptics"] = session_statistics(scene, options, in, rig, history, run_s);
  summary["interrupted"] = !completed;
  summary["inverted_steps"] = sim.inverted_steps();
  summary["unconverged_frames"] = history.unconverged();
  summary["warnings"] = warnings;
  summary["timings_s"] = {{"setup", setup_s}, {"session", run_s}, {"total", total.seconds()}};
  const bool ticks = options.keep_ticks;
  summary["outputs"] = {{"force_history_csv", ticks ? "force_history.csv" : ""},
                        {"session_csv", ticks ? "session.csv" : ""},
                        {"haptic_ticks_csv", ticks ? "haptic_ticks.csv" : ""},
                        {"surface", surface ? surface_series.pvd_relative() : ""},
                        {"tools", tool_series.pvd_relative()}};
  out.write_summary(summary);
  return summary;
}

}  // namespace vascsim
