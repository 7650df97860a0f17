#include "vascsim/run/haptic_session_setup.hpp"

#include <fmt/format.h>
#include <cmath>

#include "vascsim/core/error.hpp"
#include "vascsim/interaction/session_recording.hpp"

namespace vascsim {

namespace {

// The model the device drives; lockstep needs whole ticks per frame.
DeviceDrivenModel& driven_model(Simulation& sim, const Scene& scene, const std::string& mode) {
  DeviceDrivenModel& model = device_driven_model(sim);
  const double period = 1.0 / scene.haptics.rate_hz;
  const double frame = model.frame_length_s();
  if (mode == "lockstep" && std::abs(frame - scene.haptics.ticks_per_step * period) > 1e-9 * period)
    throw InputError(
        fmt::format("{}: key 'haptics.ticks_per_step': {} ticks of {:.4g} s must equal the frame of "
                    "model '{}' ({:.4g} s)",
                    scene.file, scene.haptics.ticks_per_step, period, scene.model, frame));
  return model;
}

}  // namespace

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
      throw InputError(fmt::format(
          "{}: key 'haptics.duration_s': a session with an external device needs a duration", scene.file));
    in.trajectory = Trajectory({DevicePose{}}, "external device");
  } else if (options.replay.empty()) {
    in.trajectory = read_trajectory(spec.trajectory);
  } else {
    RecordedSession rec = read_session_recording(options.replay);
    in.trajectory = std::move(rec.trajectory);
    in.recorded_forces = std::move(rec.forces);
  }
  in.duration_s =
      spec.duration_s > 0.0 ? spec.duration_s : in.trajectory.end_time_s() - in.trajectory.start_time_s();
  const std::string source = options.replay.empty() ? spec.trajectory : options.replay.string();
  if (!(in.duration_s > 0.0))
    throw InputError(
        fmt::format("{}: the trajectory has no duration (one sample): set haptics.duration_s", source));
  if (!(in.duration_s * spec.rate_hz <= kMaxSessionTicks))
    throw InputError(
        fmt::format("{}: the trajectory lasts {:.6g} s, {:.3g} ticks at {} Hz; a session may have at "
                    "most {:.0e} (every tick is kept in memory): shorten it or set haptics.duration_s",
                    source, in.duration_s, in.duration_s * spec.rate_hz, spec.rate_hz, kMaxSessionTicks));
  return in;
}

SessionSetup::SessionSetup(const Scene& scene, const HapticRunOptions& options)
    : inputs_(read_session_inputs(scene, options)) {  // device files first: before the slow set-up
  ticks_ = static_cast<std::size_t>(std::floor(inputs_.duration_s * scene.haptics.rate_hz + 1e-9)) + 1;
  simulation_ = std::make_unique<Simulation>(scene, options.checks);
  model_ = &driven_model(*simulation_, scene, inputs_.mode);
  // Realtime: the model may use time budgets and background work; lockstep stays deterministic.
  model_->set_realtime(inputs_.mode == "realtime");
  if (options.device != nullptr) {
    device_ = options.device;
  } else {
    scripted_ = std::make_unique<ScriptedDevice>(inputs_.trajectory, scripted_device_limits(scene.haptics));
    scripted_->reserve_forces(ticks_ + 16);
    device_ = scripted_.get();
  }
  if (!options.keep_ticks && !options.record.empty())
    throw InputError("a session that keeps no ticks cannot write a recording (--record)");
  rig_ =
      std::make_unique<HapticRig>(*model_, scene, *device_,
                                  HapticRigOptions{inputs_.tool, inputs_.trajectory.start_time_s(),
                                                   options.keep_ticks, options.keep_ticks ? ticks_ + 16 : 0});
}

double SessionSetup::frames() const {
  return std::ceil(inputs_.duration_s / model_->frame_length_s() - 1e-9);
}

}  // namespace vascsim
