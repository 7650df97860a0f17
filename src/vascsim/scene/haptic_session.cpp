#include "vascsim/scene/haptic_session.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fmt/format.h>
#include <fstream>
#include <spdlog/spdlog.h>
#include <thread>

#include "vascsim/core/error.hpp"
#include "vascsim/interaction/haptic_loop.hpp"
#include "vascsim/interaction/scripted_device.hpp"
#include "vascsim/interaction/session_recording.hpp"
#include "vascsim/io/vtk_writer.hpp"
#include "vascsim/model/xpbd_model.hpp"
#include "vascsim/scene/runner.hpp"
#include "vascsim/scene/simulation.hpp"

namespace vascsim {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_between(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

// One simulation step as force_history.csv records it.
struct SimSample {
  double sim_time_s = 0.0, pose_time_s = 0.0;
  Vec3 tool_position_m = Vec3::Zero(), force_n = Vec3::Zero(), torque_n_m = Vec3::Zero();
  int contacts = 0;
  double wall_s = 0.0;
};

// The simulation side of the session: poses the tool, steps the model, publishes the contact state with a
// secant estimate of the normal contact stiffness (ContactState: F(p) = F + K (p_sim - p), K = k n n^T).
class SimulationSide {
 public:
  SimulationSide(XpbdModel& model, std::size_t tool, double force_scale, double max_stiffness,
                 LatestValue<ContactState>& to_haptics)
      : model_(model), tool_(tool), scale_(force_scale), max_k_(max_stiffness), out_(to_haptics) {}

  SimSample step(const ToolPose& pose) {
    const auto t0 = Clock::now();
    model_.set_obstacle_pose(tool_, pose.position(), pose.orientation());
    model_.step();
    const ObstacleLoad load = model_.obstacle_loads()[tool_];
    SimSample s;
    s.sim_time_s = model_.time();
    s.pose_time_s = pose.time_s;
    s.tool_position_m = pose.position();
    s.force_n = -load.force_n;  // the tissue's force on the tool
    s.torque_n_m = -load.torque_n_m;
    s.contacts = load.contacts;
    publish(pose, scale_ * s.force_n);
    s.wall_s = seconds_between(t0, Clock::now());
    return s;
  }

 private:
  void publish(const ToolPose& pose, const Vec3& f) {
    const double magnitude = f.norm();
    const Vec3 n = magnitude > 0.0 ? Vec3(f / magnitude) : Vec3::Zero();
    if (magnitude == 0.0) {
      k_ = 0.0;
    } else if (have_previous_) {
      // Secant along the normal: moving into the tissue (along -n) raises |F|.
      const double dx = (pose.position() - previous_position_).dot(n);
      if (std::abs(dx) > 1e-7) k_ = std::clamp(-(magnitude - previous_magnitude_) / dx, 0.0, max_k_);
    }
    have_previous_ = true;
    previous_position_ = pose.position();
    previous_magnitude_ = magnitude;
    ContactState c;
    c.sequence = ++sequence_;
    c.sim_time_s = model_.time();
    c.tool = pose;
    c.set_force(f);
    c.set_stiffness(normal_stiffness(n, k_));
    c.set_normal(n);
    out_.write(c);
  }

  XpbdModel& model_;
  std::size_t tool_;
  double scale_, max_k_;
  LatestValue<ContactState>& out_;
  std::uint64_t sequence_ = 0;
  bool have_previous_ = false;
  Vec3 previous_position_ = Vec3::Zero();
  double previous_magnitude_ = 0.0, k_ = 0.0;
};

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

}  // namespace

nlohmann::json run_haptic_session(const Scene& scene, const HapticRunOptions& options) {
  namespace fs = std::filesystem;
  const HapticsSpec& spec = scene.haptics;
  if (!spec.enabled) throw InputError(fmt::format("{}: the scene has no 'haptics' block", scene.file));
  const std::size_t tool = find_tool(scene, spec.tool, "haptics.tool");
  const std::string mode = options.mode.empty() ? spec.mode : options.mode;
  if (mode != "lockstep" && mode != "realtime")
    throw InputError(fmt::format("haptic mode '{}': use lockstep or realtime", mode));
  // Device files first: a bad one fails before the (slow) set-up.
  std::vector<ForceSample> recorded_forces;
  Trajectory trajectory;
  if (options.device != nullptr) {
    if (!(spec.duration_s > 0.0))
      throw InputError(fmt::format("{}: key 'haptics.duration_s': a session with an external device needs a duration",
                                   scene.file));
    trajectory = Trajectory({DevicePose{}}, "external device");
  } else if (options.replay.empty()) {
    trajectory = read_trajectory(spec.trajectory);
  } else {
    RecordedSession rec = read_session_recording(options.replay);
    trajectory = std::move(rec.trajectory);
    recorded_forces = std::move(rec.forces);
  }
  const double duration = spec.duration_s > 0.0 ? spec.duration_s : trajectory.end_time_s() - trajectory.start_time_s();
  if (!(duration > 0.0))
    throw InputError(fmt::format("{}: the trajectory has no duration (one sample): set haptics.duration_s",
                                 options.replay.empty() ? spec.trajectory : options.replay.string()));
  std::error_code ec;
  fs::create_directories(options.out_dir, ec);
  if (ec) throw InputError(fmt::format("{}: cannot create the output folder: {}", options.out_dir.string(), ec.message()));

  const auto t_begin = Clock::now();
  Simulation sim(scene);
  auto* model = dynamic_cast<XpbdModel*>(&sim.model());
  if (model == nullptr) throw InputError(fmt::format("{}: a haptic session needs model 'xpbd'", scene.file));
  const double period = 1.0 / spec.rate_hz;
  if (mode == "lockstep" && std::abs(model->step_length() - spec.ticks_per_step * period) > 1e-9 * period)
    throw InputError(fmt::format("{}: key 'haptics.ticks_per_step': {} ticks of {:.4g} s must equal the xpbd step "
                                 "({:.4g} s, xpbd.step_s and xpbd.output_interval_s)",
                                 scene.file, spec.ticks_per_step, period, model->step_length()));
  const auto n_ticks = static_cast<std::size_t>(std::floor(duration * spec.rate_hz + 1e-9)) + 1;

  DeviceLimits limits;
  limits.max_continuous_force_n = spec.force_limit_n;
  limits.max_peak_force_n = std::max(limits.max_peak_force_n, spec.force_limit_n);
  ScriptedDevice scripted(trajectory, limits);
  scripted.reserve_forces(n_ticks + 16);
  Device& device = options.device != nullptr ? *options.device : scripted;
  if (options.device != nullptr) {
    limits = device.limits();
    limits.max_continuous_force_n = std::min(limits.max_continuous_force_n, spec.force_limit_n);
  }
  VirtualCouplingSettings cs;
  cs.proxy_mass_kg = spec.proxy_mass_kg;
  cs.stiffness_n_per_m = spec.coupling_stiffness_n_per_m;
  cs.damping_n_s_per_m = spec.coupling_damping_n_s_per_m;
  cs.max_contact_stiffness_n_per_m = limits.max_stiffness_n_per_m;
  cs.time_step_s = period;
  ForceOutputSettings fo;
  fo.max_force_n = limits.max_continuous_force_n;
  fo.max_step_n_per_tick = spec.force_step_n;
  LatestValue<ContactState> from_sim;
  LatestValue<ToolPose> to_sim;
  SessionRecording recording(n_ticks + 16);
  HapticLoopOptions lo;
  lo.rate_hz = spec.rate_hz;
  lo.record = &recording;
  lo.start_time_s = trajectory.start_time_s();
  HapticLoop loop(device, VirtualCoupling(cs), ForceOutputFilter(fo), from_sim, to_sim, lo);
  SimulationSide side(*model, tool, spec.force_scale, limits.max_stiffness_n_per_m, from_sim);
  // The tool starts where the device starts (no sweep from the scene's rest pose).
  const DevicePose first = device.pose(trajectory.start_time_s());
  model->set_obstacle_pose(tool, first.position_m, first.orientation);
  const double setup_s = seconds_between(t_begin, Clock::now());

  // Surface series at the xpbd output interval.
  const bool surface = scene.output.surface && sim.body().surface.has_value();
  const fs::path vtk_dir = options.out_dir / "vtk";
  std::vector<PvdEntry> surface_pvd;
  const long long steps_per_frame =
      std::max(1LL, std::llround(scene.xpbd.output_interval_s / model->step_length()));
  long long steps = 0;
  auto write_frame = [&]() {
    if (!surface || steps % (steps_per_frame * scene.output.vtk_every) != 0) return;
    fs::create_directories(vtk_dir, ec);
    const std::string name = fmt::format("surface_{:05d}.vtu", steps);
    write_surface_frame(sim, vtk_dir / name);
    surface_pvd.push_back({model->time(), name});
    write_pvd(vtk_dir / "surface.pvd", surface_pvd);
  };

  std::vector<SimSample> history;
  history.reserve(n_ticks / static_cast<std::size_t>(spec.ticks_per_step) + 16);
  write_frame();
  const auto t_run = Clock::now();
  double last_progress = -1.0;
  auto progress = [&](double done) {
    if (options.on_progress && done - last_progress >= 0.02 * duration) {
      options.on_progress(done, duration);
      last_progress = done;
    }
  };
  if (mode == "lockstep") {
    for (std::size_t k = 0; k < n_ticks; ++k) {
      loop.tick(trajectory.start_time_s() + static_cast<double>(k) * period);
      if (k % static_cast<std::size_t>(spec.ticks_per_step) == 0) {
        to_sim.update();
        history.push_back(side.step(to_sim.value()));
        ++steps;
        write_frame();
        progress(static_cast<double>(k) * period);
      }
    }
  } else {
    loop.start();
    try {
      for (;;) {
        const double wall = seconds_between(t_run, Clock::now());
        if (wall >= duration) break;
        to_sim.update();
        if (to_sim.value().sequence == 0) {
          std::this_thread::sleep_for(std::chrono::microseconds(100));
          continue;
        }
        history.push_back(side.step(to_sim.value()));
        ++steps;
        write_frame();
        progress(wall);
        // Never ahead of the wall clock: a fast simulation waits for real time.
        const double ahead = model->time() - seconds_between(t_run, Clock::now());
        if (ahead > 0.0) std::this_thread::sleep_for(std::chrono::duration<double>(ahead));
      }
    } catch (...) {
      loop.stop();
      throw;
    }
    loop.stop();
  }
  const double run_s = seconds_between(t_run, Clock::now());
  if (options.on_progress) options.on_progress(duration, duration);

  // Files.
  const fs::path history_csv = options.out_dir / "force_history.csv";
  {
    std::ofstream f(history_csv);
    if (!f) throw InputError(fmt::format("{}: cannot write", history_csv.string()));
    f << "sim_time_s,pose_time_s,tool_x_m,tool_y_m,tool_z_m,force_x_n,force_y_n,force_z_n,force_n,torque_x_n_m,"
         "torque_y_n_m,torque_z_n_m,contacts,step_wall_ms\n";
    for (const auto& s : history)
      f << fmt::format("{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},"
                       "{:.17g},{},{:.4f}\n",
                       s.sim_time_s, s.pose_time_s, s.tool_position_m.x(), s.tool_position_m.y(), s.tool_position_m.z(),
                       s.force_n.x(), s.force_n.y(), s.force_n.z(), s.force_n.norm(), s.torque_n_m.x(),
                       s.torque_n_m.y(), s.torque_n_m.z(), s.contacts, s.wall_s * 1e3);
  }
  const fs::path session_csv = options.out_dir / "session.csv";
  recording.write_csv(session_csv);
  if (!options.record.empty()) recording.write_csv(options.record);

  // Summary.
  std::vector<double> step_ms;
  double max_force = 0.0;
  for (const auto& s : history) {
    step_ms.push_back(s.wall_s * 1e3);
    max_force = std::max(max_force, s.force_n.norm());
  }
  const HapticStats stats = loop.stats();
  nlohmann::json haptics = {
      {"mode", mode},
      {"tool", scene.obstacles[tool].name},
      {"device", std::string(device.name())},
      {"trajectory", options.replay.empty() ? spec.trajectory : options.replay.string()},
      {"duration_s", duration},
      {"rate_hz", spec.rate_hz},
      {"ticks", recording.size()},
      {"simulation_steps", history.size()},
      {"deformation_rate_hz", run_s > 0.0 ? static_cast<double>(history.size()) / run_s : 0.0},
      {"step_wall_ms", {{"p50", quantile(step_ms, 0.5)}, {"p99", quantile(step_ms, 0.99)},
                        {"max", step_ms.empty() ? 0.0 : *std::max_element(step_ms.begin(), step_ms.end())}}},
      {"max_force_on_tool_n", max_force},
      {"force_scale", spec.force_scale},
      {"force_limit_n", spec.force_limit_n},
      {"loop", stats}};
  if (!options.replay.empty()) {
    // The replay against the recording it plays: bit-identical in lockstep on one thread.
    const auto& ticks = recording.ticks();
    const std::size_t n = std::min(ticks.size(), recorded_forces.size());
    double largest = 0.0;
    bool identical = ticks.size() == recorded_forces.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 d = ticks[i].force_n - recorded_forces[i].force_n;
      largest = std::max(largest, d.cwiseAbs().maxCoeff());
      identical = identical && d.isZero(0.0) && ticks[i].pose.time_s == recorded_forces[i].time_s;
    }
    haptics["replay"] = {{"file", options.replay.string()}, {"ticks_compared", n},
                         {"max_force_difference_n", largest}, {"bit_identical", identical}};
  }
  nlohmann::json summary = describe_run(scene, sim);
  summary["haptics"] = haptics;
  summary["timings_s"] = {{"setup", setup_s}, {"session", run_s}, {"total", seconds_between(t_begin, Clock::now())}};
  summary["outputs"] = {{"force_history_csv", history_csv.filename().string()},
                        {"session_csv", session_csv.filename().string()},
                        {"surface", surface ? "vtk/surface.pvd" : ""}};
  std::ofstream js(options.out_dir / "summary.json");
  js << summary.dump(2) << "\n";
  if (!js) throw InputError(fmt::format("{}: cannot write summary.json", options.out_dir.string()));
  return summary;
}

}  // namespace vascsim
