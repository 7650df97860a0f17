#include "vascsim/run/haptic_session.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <memory>
#include <thread>

#include "vascsim/core/error.hpp"
#include "vascsim/core/interrupt.hpp"
#include "vascsim/core/statistics.hpp"
#include "vascsim/core/stopwatch.hpp"
#include "vascsim/interaction/scripted_device.hpp"
#include "vascsim/interaction/session_recording.hpp"
#include "vascsim/model/registry.hpp"
#include "vascsim/run/haptic_rig.hpp"
#include "vascsim/run/output_writer.hpp"
#include "vascsim/run/realtime_pacing.hpp"
#include "vascsim/run/runner.hpp"

namespace vascsim {

namespace {

// What the session plays: the device's trajectory (or a recording), checked before the slow set-up.
struct SessionInputs {
  std::size_t tool = 0;
  std::string mode;
  Trajectory trajectory;
  std::vector<ForceSample> recorded_forces;  // when replaying
  double duration_s = 0.0;
};

SessionInputs read_session_inputs(const Scene& scene, const HapticRunOptions& options) {
  const HapticsSpec& spec = scene.haptics;
  if (!spec.enabled) throw InputError(fmt::format("{}: the scene has no 'haptics' block", scene.file));
  SessionInputs in;
  in.tool = find_tool(scene, spec.tool, "haptics.tool");
  in.mode = options.mode.empty() ? spec.mode : options.mode;
  if (in.mode != "lockstep" && in.mode != "realtime")
    throw InputError(fmt::format("haptic mode '{}': use lockstep or realtime", in.mode));
  if (options.device != nullptr) {
    if (!(spec.duration_s > 0.0))
      throw InputError(fmt::format("{}: key 'haptics.duration_s': a session with an external device needs a duration",
                                   scene.file));
    in.trajectory = Trajectory({DevicePose{}}, "external device");
  } else if (options.replay.empty()) {
    in.trajectory = read_trajectory(spec.trajectory);
  } else {
    RecordedSession rec = read_session_recording(options.replay);
    in.trajectory = std::move(rec.trajectory);
    in.recorded_forces = std::move(rec.forces);
  }
  in.duration_s = spec.duration_s > 0.0 ? spec.duration_s
                                        : in.trajectory.end_time_s() - in.trajectory.start_time_s();
  const std::string source = options.replay.empty() ? spec.trajectory : options.replay.string();
  if (!(in.duration_s > 0.0))
    throw InputError(fmt::format("{}: the trajectory has no duration (one sample): set haptics.duration_s", source));
  if (!(in.duration_s * spec.rate_hz <= kMaxSessionTicks))
    throw InputError(fmt::format("{}: the trajectory lasts {:.6g} s, {:.3g} ticks at {} Hz; a session may have at "
                                 "most {:.0e} (every tick is kept in memory): shorten it or set haptics.duration_s",
                                 source, in.duration_s, in.duration_s * spec.rate_hz, spec.rate_hz, kMaxSessionTicks));
  return in;
}

// The model the device drives; lockstep needs whole ticks per frame.
DeviceDrivenModel& driven_model(Simulation& sim, const Scene& scene, const std::string& mode) {
  DeviceDrivenModel& model = device_driven_model(sim);
  const double period = 1.0 / scene.haptics.rate_hz;
  const double frame = model.frame_length_s();
  if (mode == "lockstep" && std::abs(frame - scene.haptics.ticks_per_step * period) > 1e-9 * period)
    throw InputError(fmt::format("{}: key 'haptics.ticks_per_step': {} ticks of {:.4g} s must equal the frame of "
                                 "model '{}' ({:.4g} s)",
                                 scene.file, scene.haptics.ticks_per_step, period, scene.model, frame));
  return model;
}

// The device the session plays: the scene's scripted trajectory (or a recording), or the caller's.
struct SessionDevice {
  std::unique_ptr<ScriptedDevice> scripted;
  Device* device = nullptr;
};

SessionDevice session_device(const Scene& scene, const HapticRunOptions& options, const SessionInputs& in,
                             std::size_t n_ticks) {
  SessionDevice d;
  if (options.device != nullptr) {
    d.device = options.device;
    return d;
  }
  d.scripted = std::make_unique<ScriptedDevice>(in.trajectory, scripted_device_limits(scene.haptics));
  d.scripted->reserve_forces(n_ticks + 16);
  d.device = d.scripted.get();
  return d;
}

// Calls on_progress about every 2 % of the session.
class ProgressThrottle {
 public:
  ProgressThrottle(const HapticRunOptions& options, double duration) : options_(options), duration_(duration) {}
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

// The frames of a session: every one, or (keep_ticks false: soaks) the newest kRecentFrames in a ring, so that
// memory stays constant however long the session runs; the count and the largest force cover all of them.
class FrameLog {
 public:
  static constexpr std::size_t kRecentFrames = 1 << 16;
  FrameLog(bool keep_all, std::size_t expected) : keep_all_(keep_all) {
    frames_.reserve(keep_all ? expected : kRecentFrames);
  }
  void add(const FrameSample& s) {
    max_force_n_ = std::max(max_force_n_, s.force_n.norm());
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

 private:
  bool keep_all_;
  std::vector<FrameSample> frames_;
  std::size_t count_ = 0;
  double max_force_n_ = 0.0;
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
  return fmt::format("{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},"
                     "{:.17g},{},{:.3g},{},{:.4f}",
                     s.sim_time_s, s.pose_time_s, s.tool_position_m.x(), s.tool_position_m.y(), s.tool_position_m.z(),
                     s.force_n.x(), s.force_n.y(), s.force_n.z(), s.force_n.norm(), s.torque_n_m.x(),
                     s.torque_n_m.y(), s.torque_n_m.z(), s.contacts, s.residual, s.converged ? 1 : 0, s.wall_s * 1e3);
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

nlohmann::json session_statistics(const Scene& scene, const HapticRunOptions& options, const SessionInputs& in,
                                  const HapticRig& rig, const FrameLog& history, double run_s) {
  std::vector<double> step_ms;
  for (const auto& s : history.frames()) step_ms.push_back(s.wall_s * 1e3);
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
      {"force_scale", spec.force_scale},
      {"force_limit_n", spec.force_limit_n},
      {"loop", rig.loop().stats()}};
  if (!options.replay.empty()) haptics["replay"] = replay_comparison(options, rig.recording(), in.recorded_forces);
  return haptics;
}

}  // namespace

std::vector<std::string> force_history_columns() {
  return {"sim_time_s",   "pose_time_s",  "tool_x_m",     "tool_y_m", "tool_z_m", "force_x_n",
          "force_y_n",    "force_z_n",    "force_n",      "torque_x_n_m", "torque_y_n_m", "torque_z_n_m",
          "contacts",     "residual",     "converged",    "step_wall_ms"};
}

nlohmann::json run_haptic_session(const Scene& scene, const HapticRunOptions& options) {
  const HapticsSpec& spec = scene.haptics;
  const SessionInputs in = read_session_inputs(scene, options);  // device files first: before the slow set-up
  const OutputWriter out(options.out_dir);

  const Stopwatch total;
  Simulation sim(scene);
  DeviceDrivenModel& model = driven_model(sim, scene, in.mode);
  // Realtime: the model may use time budgets and background work; lockstep stays deterministic.
  model.set_realtime(in.mode == "realtime");
  const auto n_ticks = static_cast<std::size_t>(std::floor(in.duration_s * spec.rate_hz + 1e-9)) + 1;
  const SessionDevice device = session_device(scene, options, in, n_ticks);
  if (!options.keep_ticks && !options.record.empty())
    throw InputError("a session that keeps no ticks cannot write a recording (--record)");
  HapticRig rig(model, scene, *device.device,
                {in.tool, in.trajectory.start_time_s(), options.keep_ticks, options.keep_ticks ? n_ticks + 16 : 0});
  const double setup_s = total.seconds();

  // Surface series at the model's output interval (every frame for a load-stepped model).
  const ModelEntry& entry = find_model(scene.model);
  const bool surface = scene.output.surface && sim.body().surface.has_value();
  VtkSeries surface_series = out.series("surface");
  const double output_interval = entry.schedule ? entry.schedule(scene.own_model_settings()).output_interval_s
                                                : model.frame_length_s();
  const long long frames_per_output = std::max(1LL, std::llround(output_interval / model.frame_length_s()));
  long long frames = 0;
  auto write_frame = [&]() {
    if (!surface || frames % (frames_per_output * scene.output.vtk_every) != 0) return;
    surface_series.add_surface(model.time(), fmt::format("surface_{:05d}.vtu", frames), sim.surface_frame(),
                               *sim.body().surface);
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
  const bool completed = in.mode == "lockstep" ? run_lockstep(scene, n_ticks, rig, history, after_frame, progress)
                                               : run_realtime(in, rig, model, history, after_frame, progress);
  const double run_s = run.seconds();
  if (options.on_progress) options.on_progress(in.duration_s, in.duration_s);

  if (options.keep_ticks) {
    CsvTable history_csv = out.table("force_history.csv", force_history_columns());
    for (const auto& s : history.frames()) history_csv.add_row(history_row(s));
    rig.recording().write_csv(out.path("session.csv"));
    rig.recording().write_ticks_csv(out.path("haptic_ticks.csv"));
    if (!options.record.empty()) rig.recording().write_csv(options.record);
  }

  nlohmann::json summary = describe_run(scene, sim);
  summary["haptics"] = session_statistics(scene, options, in, rig, history, run_s);
  summary["interrupted"] = !completed;
  summary["inverted_steps"] = sim.inverted_steps();
  summary["timings_s"] = {{"setup", setup_s}, {"session", run_s}, {"total", total.seconds()}};
  const bool ticks = options.keep_ticks;
  summary["outputs"] = {{"force_history_csv", ticks ? "force_history.csv" : ""},
                        {"session_csv", ticks ? "session.csv" : ""},
                        {"haptic_ticks_csv", ticks ? "haptic_ticks.csv" : ""},
                        {"surface", surface ? surface_series.pvd_relative() : ""}};
  out.write_summary(summary);
  return summary;
}

}  // namespace vascsim
