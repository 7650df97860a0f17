#pragma once
// What every driver of a device-driven model shares (the headless haptic session, the viewer): the device
// inside the 1 kHz haptic loop (virtual coupling, output filter, the two LatestValue hand-offs, the session
// recording) and the contact publisher that steps the model with the loop's newest tool pose.
//
//   device --pose--> HapticLoop --ToolPose--> ContactPublisher::step (DeviceDrivenModel) --ContactState--+
//      ^                  ^                                                                               |
//      +---- force -------+-------------------------------------------------------------------------------+
//
// Two ways to run it (docs/haptics.md):
//  - lockstep_frame(k): on the caller's thread; ticks the loop at the nominal times up to tick k and steps
//    the model with the pose of tick k. Deterministic: a recorded session replays bit for bit.
//  - start(), realtime_frame(), stop(): the loop on its own thread at wall-clock rate; realtime_frame() steps
//    the model with the newest pose on the caller's (simulation) thread. Only the two hand-offs and the
//    loop's statistics are shared between the threads.

#include <cstddef>

#include "vascsim/interaction/haptic_loop.hpp"
#include "vascsim/model/device_driven_model.hpp"
#include "vascsim/run/contact_publisher.hpp"
#include "vascsim/run/simulation.hpp"

namespace vascsim {

struct HapticRigOptions {
  std::size_t tool = 0;           ///< index into the problem's tools (find_tool)
  double start_time_s = 0.0;      ///< the haptic clock at tick 0 (where a trajectory starts playing)
  bool record = true;             ///< record every tick (recording())
  std::size_t reserve_ticks = 0;  ///< recording capacity, so the haptic thread does not allocate
};

/// The simulation's model as a device drives it. Throws InputError naming the scene and the model when no
/// device can drive it (registry capability device_driven).
DeviceDrivenModel& device_driven_model(Simulation& simulation);

/// The limits a scripted (or replaying) device gets in a scene: the haptics block's force limit is its clamp.
DeviceLimits scripted_device_limits(const HapticsSpec& haptics);

class HapticRig {
 public:
  /// `model` and `device` must outlive the rig. The clamp is the smaller of the device's continuous force and
  /// the scene's haptics.force_limit_n. The tool starts where the device is at start_time_s (no sweep from
  /// the scene's rest pose). Throws InputError for settings the loop refuses (an unstable coupling).
  HapticRig(DeviceDrivenModel& model, const Scene& scene, Device& device, const HapticRigOptions& options);

  /// Lockstep: ticks the loop through tick k at the nominal times (the ticks not made yet) and steps the
  /// model with the pose of tick k.
  FrameSample lockstep_frame(std::size_t k);
  /// Lockstep: ticks the loop through tick k without stepping the model.
  void tick_through(std::size_t k);

  /// Realtime: the loop on its own thread (stop() joins it; the destructor too).
  void start() { loop_.start(); }
  void stop() { loop_.stop(); }
  /// Realtime: steps the model with the newest pose the loop published; false (nothing stepped) before the
  /// loop's first tick.
  bool realtime_frame(FrameSample& sample);

  /// The pose the last frame used.
  const ToolPose& last_pose() const { return last_pose_; }
  /// Safe from any thread while the loop runs (stats()); the rest only while it is stopped.
  const HapticLoop& loop() const { return loop_; }
  /// Every tick's device pose and sent force; read it only while the loop is stopped.
  const SessionRecording& recording() const { return recording_; }
  const DeviceLimits& limits() const { return limits_; }
  const Device& device() const { return device_; }
  std::size_t tool() const { return tool_; }

 private:
  Device& device_;
  std::size_t tool_;
  double start_time_s_, period_s_;
  DeviceLimits limits_;
  LatestValue<ContactState> from_sim_;
  LatestValue<ToolPose> to_sim_;
  SessionRecording recording_;
  HapticLoop loop_;
  ContactPublisher publisher_;
  ToolPose last_pose_;
  std::size_t next_tick_ = 0;
};

}  // namespace vascsim
