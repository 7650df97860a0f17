#include "vascsim/run/haptic_session.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <memory>
#include <omp.h>
#include <thread>

#include "vascsim/core/error.hpp"
#include "vascsim/core/statistics.hpp"
#include "vascsim/core/stopwatch.hpp"
#include "vascsim/interaction/haptic_loop.hpp"
#include "vascsim/interaction/scripted_device.hpp"
#include "vascsim/interaction/session_recording.hpp"
#include "vascsim/model/registry.hpp"
#include "vascsim/run/contact_publisher.hpp"
#include "vascsim/run/output_writer.hpp"
#include "vascsim/run/runner.hpp"
#include "vascsim/run/simulation.hpp"

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
  if (!(in.duration_s > 0.0))
    throw InputError(fmt::format("{}: the trajectory has no duration (one sample): set haptics.duration_s",
                                 options.replay.empty() ? spec.trajectory : options.replay.string()));
  return in;
}

// The model the device drives; lockstep needs whole ticks per frame.
DeviceDrivenModel& driven_model(Simulation& sim, const Scene& scene, const std::string& mode) {
  DeviceDrivenModel* model = sim.model().device_driven();
  if (model == nullptr)
    throw InputError(fmt::format("{}: model '{}' cannot be driven by a device (haptic session)", scene.file,
                                 scene.model));
  const double period = 1.0 / scene.haptics.rate_hz;
  const double frame = model->frame_length_s();
  if (mode == "lockstep" && std::abs(frame - scene.haptics.ticks_per_step * period) > 1e-9 * period)
    throw InputError(fmt::format("{}: key 'haptics.ticks_per_step': {} ticks of {:.4g} s must equal the frame of "
                                 "model '{}' ({:.4g} s)",
                                 scene.file, scene.haptics.ticks_per_step, period, scene.model, frame));
  return *model;
}

// The haptic side: device, virtual coupling, output filter, the two hand-offs and the recording.
struct HapticSide {
  DeviceLimits limits;
  std::unique_ptr<ScriptedDevice> scripted;
  Device* device = nullptr;
  LatestValue<ContactState> from_sim;
  LatestValue<ToolPose> to_sim;
  std::unique_ptr<SessionRecording> recording;
  std::unique_ptr<HapticLoop> loop;
};

void build_haptic_side(const Scene& scene, const HapticRunOptions& options, const SessionInputs& in,
                       std::size_t n_ticks, HapticSide& h) {
  const HapticsSpec& spec = scene.haptics;
  h.limits.max_continuous_force_n = spec.force_limit_n;
  h.limits.max_peak_force_n = std::max(h.limits.max_peak_force_n, spec.force_limit_n);
  h.scripted = std::make_unique<ScriptedDevice>(in.trajectory, h.limits);
  h.scripted->reserve_forces(n_ticks + 16);
  h.device = options.device != nullptr ? options.device : h.scripted.get();
  if (options.device != nullptr) {
    h.limits = h.device->limits();
    h.limits.max_continuous_force_n = std::min(h.limits.max_continuous_force_n, spec.force_limit_n);
  }
  VirtualCouplingSettings cs;
  cs.proxy_mass_kg = spec.proxy_mass_kg;
  cs.stiffness_n_per_m = spec.coupling_stiffness_n_per_m;
  cs.damping_n_s_per_m = spec.coupling_damping_n_s_per_m;
  cs.max_contact_stiffness_n_per_m = h.limits.max_stiffness_n_per_m;
  cs.time_step_s = 1.0 / spec.rate_hz;
  ForceOutputSettings fo;
  fo.max_force_n = h.limits.max_continuous_force_n;
  fo.max_step_n_per_tick = spec.force_step_n;
  h.recording = std::make_unique<SessionRecording>(n_ticks + 16);
  HapticLoopOptions lo;
  lo.rate_hz = spec.rate_hz;
  lo.record = h.recording.get();
  lo.start_time_s = in.trajectory.start_time_s();
  h.loop = std::make_unique<HapticLoop>(*h.device, VirtualCoupling(cs), ForceOutputFilter(fo), h.from_sim, h.to_sim,
                                        lo);
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

// Lockstep: one thread; the loop ticks at the nominal times and the model steps every ticks_per_step ticks
// with the pose of that tick. Deterministic.
void run_lockstep(const Scene& scene, const SessionInputs& in, std::size_t n_ticks, HapticSide& h,
                  ContactPublisher& publisher, std::vector<FrameSample>& history,
                  const std::function<void()>& after_frame, ProgressThrottle& progress) {
  const double period = 1.0 / scene.haptics.rate_hz;
  const auto per_frame = static_cast<std::size_t>(scene.haptics.ticks_per_step);
  for (std::size_t k = 0; k < n_ticks; ++k) {
    h.loop->tick(in.trajectory.start_time_s() + static_cast<double>(k) * period);
    if (k % per_frame == 0) {
      h.to_sim.update();
      history.push_back(publisher.step(h.to_sim.value()));
      after_frame();
      progress(static_cast<double>(k) * period);
    }
  }
}

// Realtime: the haptic loop on its own thread at wall-clock rate, the model on this thread as fast as it can
// (never ahead of the wall clock); only the two LatestValue hand-offs are shared.
// The deformation leaves one core to the haptic thread: an OpenMP team spinning on every core starves it
// (measured: 918 Hz and a 3.9 ms p99 jitter with a solve on both cores). Restored when the session ends.
class DeformationThreads {
 public:
  DeformationThreads() : saved_(omp_get_max_threads()) {
    omp_set_num_threads(std::max(1, static_cast<int>(std::thread::hardware_concurrency()) - 1));
  }
  ~DeformationThreads() { omp_set_num_threads(saved_); }
  DeformationThreads(const DeformationThreads&) = delete;
  DeformationThreads& operator=(const DeformationThreads&) = delete;

 private:
  int saved_;
};

void run_realtime(const SessionInputs& in, HapticSide& h, DeviceDrivenModel& model, ContactPublisher& publisher,
                  std::vector<FrameSample>& history, const std::function<void()>& after_frame,
                  ProgressThrottle& progress) {
  const DeformationThreads threads;
  h.loop->start();
  try {
    const Stopwatch run;
    for (;;) {
      const double wall = run.seconds();
      if (wall >= in.duration_s) break;
      h.to_sim.update();
      if (h.to_sim.value().sequence == 0) {
        std::this_thread::sleep_for(std::chrono::microseconds(100));
        continue;
      }
      history.push_back(publisher.step(h.to_sim.value()));
      after_frame();
      progress(wall);
      const double ahead = model.time() - run.seconds();
      if (ahead > 0.0) std::this_thread::sleep_for(std::chrono::duration<double>(ahead));
    }
  } catch (...) {
    h.loop->stop();
    throw;
  }
  h.loop->stop();
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
                                  const HapticSide& h, const std::vector<FrameSample>& history, double run_s) {
  std::vector<double> step_ms;
  double max_force = 0.0;
  for (const auto& s : history) {
    step_ms.push_back(s.wall_s * 1e3);
    max_force = std::max(max_force, s.force_n.norm());
  }
  const HapticsSpec& spec = scene.haptics;
  nlohmann::json haptics = {
      {"mode", in.mode},
      {"tool", scene.obstacles[in.tool].name},
      {"device", std::string(h.device->name())},
      {"trajectory", options.replay.empty() ? spec.trajectory : options.replay.string()},
      {"duration_s", in.duration_s},
      {"rate_hz", spec.rate_hz},
      {"ticks", h.recording->size()},
      {"simulation_steps", history.size()},
      {"deformation_rate_hz", run_s > 0.0 ? static_cast<double>(history.size()) / run_s : 0.0},
      {"step_wall_ms",
       {{"p50", quantile(step_ms, 0.5)},
        {"p99", quantile(step_ms, 0.99)},
        {"max", step_ms.empty() ? 0.0 : *std::max_element(step_ms.begin(), step_ms.end())}}},
      {"max_force_on_tool_n", max_force},
      {"force_scale", spec.force_scale},
      {"force_limit_n", spec.force_limit_n},
      {"loop", h.loop->stats()}};
  if (!options.replay.empty()) haptics["replay"] = replay_comparison(options, *h.recording, in.recorded_forces);
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
  HapticSide h;
  build_haptic_side(scene, options, in, n_ticks, h);
  ContactPublisher publisher(model, in.tool, spec.force_scale, h.limits.max_stiffness_n_per_m, h.from_sim);
  // The tool starts where the device starts (no sweep from the scene's rest pose).
  const DevicePose first = h.device->pose(in.trajectory.start_time_s());
  model.set_tool_pose(in.tool, first.position_m, first.orientation);
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
    write_frame();
  };

  std::vector<FrameSample> history;
  history.reserve(n_ticks / static_cast<std::size_t>(spec.ticks_per_step) + 16);
  write_frame();
  ProgressThrottle progress(options, in.duration_s);
  const Stopwatch run;
  if (in.mode == "lockstep")
    run_lockstep(scene, in, n_ticks, h, publisher, history, after_frame, progress);
  else
    run_realtime(in, h, model, publisher, history, after_frame, progress);
  const double run_s = run.seconds();
  if (options.on_progress) options.on_progress(in.duration_s, in.duration_s);

  CsvTable history_csv = out.table("force_history.csv", force_history_columns());
  for (const auto& s : history) history_csv.add_row(history_row(s));
  h.recording->write_csv(out.path("session.csv"));
  h.recording->write_ticks_csv(out.path("haptic_ticks.csv"));
  if (!options.record.empty()) h.recording->write_csv(options.record);

  nlohmann::json summary = describe_run(scene, sim);
  summary["haptics"] = session_statistics(scene, options, in, h, history, run_s);
  summary["timings_s"] = {{"setup", setup_s}, {"session", run_s}, {"total", total.seconds()}};
  summary["outputs"] = {{"force_history_csv", "force_history.csv"},
                        {"session_csv", "session.csv"},
                        {"haptic_ticks_csv", "haptic_ticks.csv"},
                        {"surface", surface ? surface_series.pvd_relative() : ""}};
  out.write_summary(summary);
  return summary;
}

}  // namespace vascsim
