#include "vascsim/run/live_session.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>
#include <cmath>

#include "vascsim/core/error.hpp"
#include "vascsim/core/stopwatch.hpp"
#include "vascsim/interaction/scripted_device.hpp"
#include "vascsim/interaction/session_recording.hpp"
#include "vascsim/model/registry.hpp"
#include "vascsim/run/haptic_rig.hpp"

namespace vascsim {

namespace {

using Kind = LiveCommand::Kind;

// A model has diverged when kDivergedFrames frames in a row end with a relative force residual above
// kDivergedResidual (StepReport.residual; 0 when not reported). One or two such frames are normal where a
// contact begins: the implicit model's lockstep press has 1.65 for two frames at the touch, then 0.07, 0.008;
// when the device outruns it on a loaded machine it stays at 1.4-15 (the realtime session's force history).
constexpr double kDivergedResidual = 1.0;
constexpr int kDivergedFrames = 5;

// The trajectory a scripted device plays for a replay or the scene's own trajectory; none otherwise.
std::optional<Trajectory> played_trajectory(const Scene& scene, Kind kind,
                                            const std::filesystem::path& file) {
  if (kind == Kind::replay) return read_session_recording(file).trajectory;
  if (kind != Kind::play_trajectory) return std::nullopt;
  if (!scene.haptics.enabled)
    throw InputError(
        fmt::format("{}: the scene has no scripted trajectory (no 'haptics' block)", scene.file));
  return read_trajectory(scene.haptics.trajectory);
}

std::optional<std::size_t> driven_tool(const Scene& scene) {
  if (scene.obstacles.empty()) return std::nullopt;
  return find_tool(scene, scene.haptics.tool, "haptics.tool");
}

std::string describe(Kind kind, const Scene& scene, const std::filesystem::path& file) {
  switch (kind) {
    case Kind::start_recording:
      return "recording from the rest state";
    case Kind::replay:
      return fmt::format("replaying {}", file.string());
    case Kind::play_trajectory:
      return fmt::format("playing {}", scene.haptics.trajectory);
    default:
      return fmt::format("{}: model {}", scene.name, scene.model);
  }
}

}  // namespace

LiveSession::LiveSession(const Scene& scene, Device& device, LiveObserver& observer,
                         const LiveOptions& options)
    : interactive_(device), observer_(observer), options_(options), scene_(scene) {
  build(scene, options.start, options.start_file);
}

LiveSession::~LiveSession() {
  stop();
  stop_rig();
}

void LiveSession::start() {
  if (options_.lockstep || thread_.joinable()) return;
  stop_.store(false, std::memory_order_relaxed);
  thread_ = std::thread([this] { run(); });
}

void LiveSession::stop() {
  stop_.store(true, std::memory_order_relaxed);
  if (thread_.joinable()) thread_.join();
}

void LiveSession::stop_rig() {
  if (rig_) rig_->stop();
}

void LiveSession::build(const Scene& scene, Kind kind, const std::filesystem::path& file) {
  // Everything the user chose is checked before the running simulation is replaced: a bad file or scene
  // leaves it running.
  if (!find_model(scene.model).capabilities.device_driven)
    throw InputError(fmt::format(
        "{}: model '{}' cannot be driven by a device; use one of: {} (--set model=...)", scene.file,
        scene.model, fmt::join(model_names_with(&ModelCapabilities::device_driven), ", ")));
  const std::optional<Trajectory> trajectory = played_trajectory(scene, kind, file);
  auto simulation = std::make_unique<Simulation>(scene);
  DeviceDrivenModel& model = device_driven_model(*simulation);
  const std::optional<std::size_t> tool = driven_tool(scene);

  stop_rig();
  rig_.reset();
  scripted_.reset();
  simulation_ = std::move(simulation);
  model_ = &model;
  scene_ = scene;
  tool_ = tool;
  model_->set_realtime(!options_.lockstep);
  observer_.built(*simulation_, tool_);
  const std::uint64_t build = info_.build + 1;
  info_ = LiveFrameInfo{};
  info_.build = build;
  info_.paused = paused();
  info_.message = describe(kind, scene_, file);
  info_.sample.sim_time_s = model_->time();
  next_tick_ = 0;
  recent_frames_.clear();
  diverged_frames_ = 0;
  if (tool_) {
    Device* device = &interactive_;
    double start_s = 0.0;
    if (trajectory) {
      scripted_ = std::make_unique<ScriptedDevice>(*trajectory, scripted_device_limits(scene_.haptics));
      device = scripted_.get();
      start_s = trajectory->start_time_s();
    }
    const bool record = kind == Kind::start_recording;
    rig_ = std::make_unique<HapticRig>(
        *model_, scene_, *device, HapticRigOptions{*tool_, start_s, record, options_.record_reserve_ticks});
    info_.has_tool = true;
    info_.recording = record;
    info_.device = std::string(device->name());
    info_.tool_orientation = rig_->last_pose().orientation();
    info_.sample.tool_position_m = rig_->last_pose().position();
  }
  publish();
  if (thread_.joinable() && rig_) rig_->start();
  clock_.sync(model_->time());
}

void LiveSession::write_recording(const std::filesystem::path& file) {
  if (!rig_ || !info_.recording) {
    info_.message = "not recording: press record first";
    return;
  }
  rig_->stop();  // the recording may be read only while the loop is stopped
  const std::size_t ticks = rig_->recording().size();
  try {
    rig_->recording().write_csv(file);
    info_.message = fmt::format("wrote {} ({} ticks, {:.1f} s)", file.string(), ticks,
                                static_cast<double>(ticks) / scene_.haptics.rate_hz);
  } catch (const InputError& e) {
    info_.message = e.what();
  }
  // Go on without recording, with the device where it is now.
  Device& device = scripted_ ? static_cast<Device&>(*scripted_) : interactive_;
  rig_ = std::make_unique<HapticRig>(*model_, scene_, device, HapticRigOptions{*tool_, 0.0, false, 0});
  info_.recording = false;
  if (thread_.joinable()) rig_->start();
}

void LiveSession::apply(const LiveCommand& c) {
  try {
    switch (c.kind) {
      case Kind::stop_recording:
        write_recording(c.file);
        break;
      case Kind::load:
        build(*c.scene, Kind::load, {});
        break;
      default:
        build(scene_, c.kind, c.file);
        break;
    }
  } catch (const InputError& e) {
    info_.message = fmt::format("error: {}", e.what());
  } catch (const NumericalError& e) {
    info_.message = fmt::format("numerical error: {}", e.what());
  }
}

bool LiveSession::step_frame() {
  FrameSample s;
  if (rig_) {
    if (options_.lockstep) {
      s = rig_->lockstep_frame(next_tick_);
      next_tick_ += static_cast<std::size_t>(
          std::max(1LL, std::llround(model_->frame_length_s() * scene_.haptics.rate_hz)));
    } else if (!rig_->realtime_frame(s)) {
      return false;  // the haptic loop has not ticked yet
    }
    info_.tool_orientation = rig_->last_pose().orientation();
  } else {
    const Stopwatch clock;
    const StepReport r = model_->step();
    s.sim_time_s = model_->time();
    s.residual = r.residual;
    s.converged = r.converged;
    s.wall_s = clock.seconds();
  }
  info_.sample = s;
  ++info_.frame;
  diverged_frames_ = s.residual > kDivergedResidual ? diverged_frames_ + 1 : 0;
  if (diverged_frames_ >= kDivergedFrames) {
    // Forces out of balance by more than the forces themselves, frame after frame: the state is no longer a
    // deformation of the vessel (too fast or too deep a push for the model). Stop rather than go on showing
    // it; the device's clamp held.
    paused_.store(true, std::memory_order_relaxed);
    info_.paused = true;
    info_.message = fmt::format(
        "paused: the model diverged (relative residual {:.3g} > {:g} for {} frames); reset "
        "to go on",
        s.residual, kDivergedResidual, diverged_frames_);
    diverged_frames_ = 0;
  }
  const double now = clock_.seconds();
  recent_frames_.push_back(now);
  while (!recent_frames_.empty() && recent_frames_.front() < now - 1.0)
    recent_frames_.erase(recent_frames_.begin());
  info_.steps_per_s = static_cast<double>(recent_frames_.size());
  return true;
}

void LiveSession::publish() {
  if (rig_) info_.haptics = rig_->loop().stats();
  observer_.frame(*simulation_, info_);
}

void LiveSession::step_lockstep() {
  for (const LiveCommand& c : mailbox_.take()) apply(c);
  info_.paused = paused();
  if (info_.paused) {
    if (steps_requested_.load(std::memory_order_relaxed) == 0) return publish();
    steps_requested_.fetch_sub(1, std::memory_order_relaxed);
  }
  step_frame();
  publish();
}

void LiveSession::run() {
  const DeformationThreads threads;
  if (rig_) rig_->start();
  clock_.sync(model_->time());
  Stopwatch since_refresh;
  while (!stop_.load(std::memory_order_relaxed)) {
    try {
      for (const LiveCommand& c : mailbox_.take()) apply(c);
      const bool paused = this->paused();
      if (paused != info_.paused) {
        info_.paused = paused;
        clock_.sync(
            model_->time());  // resume where the model is: no sleeping off or racing through the pause
      }
      if (paused && steps_requested_.load(std::memory_order_relaxed) == 0) {
        if (since_refresh.seconds() >= options_.paused_refresh_s) {
          publish();
          since_refresh.restart();
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
        continue;
      }
      if (paused) steps_requested_.fetch_sub(1, std::memory_order_relaxed);
      if (!step_frame()) {
        std::this_thread::sleep_for(std::chrono::microseconds(100));
        continue;
      }
      publish();
      if (paused)
        clock_.sync(model_->time());
      else
        clock_.wait_for(model_->time());
    } catch (const std::exception& e) {
      // A frame failed (a non-finite state): stop stepping, tell the user, keep the window alive.
      spdlog::error("simulation: {}", e.what());
      info_.message = fmt::format("stopped: {} (reset to go on)", e.what());
      paused_.store(true, std::memory_order_relaxed);
      info_.paused = true;
    }
  }
  stop_rig();
}

}  // namespace vascsim
