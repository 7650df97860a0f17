#pragma once
// A device-driven simulation running live: what the viewer drives (docs/viewer.md). The scene's model (any
// registry model with device_driven, only through DeviceDrivenModel) steps in real time while a device poses
// the tool through the 1 kHz haptic loop: the same HapticRig as a realtime haptic session
// (haptic_session.hpp). After every frame the session hands the simulation to an observer (the viewer's frame
// builder), which publishes a snapshot of the surface for the render thread (core/frame_exchange.hpp).
//
//   UI thread --commands (mailbox), pause/step (atomics)--> simulation thread --observer--> render thread
//   device input (the device's own hand-off) --> haptic thread <--LatestValue x2--> simulation thread
//
// Two modes:
//  - realtime (a window): start() runs the simulation thread, which never runs ahead of the wall clock and
//    never waits for the UI or the renderer; the haptic loop has its own thread.
//  - lockstep (headless pictures): no threads; step_lockstep() ticks the loop at the nominal times and steps
//    the model once on the caller's thread. Deterministic.
// A scene without a tool runs without the haptic loop (the device drives nothing); its model still steps.

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "vascsim/interaction/device.hpp"
#include "vascsim/interaction/haptic_loop.hpp"
#include "vascsim/run/contact_publisher.hpp"
#include "vascsim/run/live_commands.hpp"
#include "vascsim/run/realtime_pacing.hpp"
#include "vascsim/run/simulation.hpp"

namespace vascsim {

class HapticRig;
class ScriptedDevice;

/// What the observer gets with every frame.
struct LiveFrameInfo {
  std::uint64_t build = 0;  ///< 1, 2, ... per (re)build: the surface's topology may have changed
  std::uint64_t frame = 0;  ///< frames stepped since the build; 0: the rest state
  bool has_tool = false;    ///< a device drives a tool (the haptic loop runs)
  FrameSample sample;       ///< the frame: tool position, force on the tool, residual, wall time
  Eigen::Quaterniond tool_orientation = Eigen::Quaterniond::Identity();
  double steps_per_s = 0.0;  ///< deformation frames per wall-clock second over the last second
  HapticStats haptics;       ///< the haptic loop's statistics (zero without a tool)
  bool paused = false, recording = false;
  std::string device;   ///< the device driving the tool ("mouse_keyboard", "scripted", ...)
  std::string message;  ///< the latest notice or error for the user ("" : none)
};

class LiveObserver {
 public:
  virtual ~LiveObserver() = default;
  /// A simulation was (re)built, before the tool is posed: prepare for it (e.g. place the interactive
  /// device's workspace at `tool`, the index of the driven tool, if any). On the thread that builds.
  virtual void built(Simulation& simulation, std::optional<std::size_t> tool) = 0;
  /// After every frame and once for the rest state of every build, on the simulation thread (the caller's in
  /// lockstep). `simulation` may be read during the call only.
  virtual void frame(Simulation& simulation, const LiveFrameInfo& info) = 0;
};

struct LiveOptions {
  bool lockstep = false;  ///< no threads: step_lockstep() on the caller's thread
  /// What drives the tool from the start: the interactive device (reset), the scene's trajectory
  /// (play_trajectory) or the recording `start_file` (replay).
  LiveCommand::Kind start = LiveCommand::Kind::reset;
  std::filesystem::path start_file;
  /// A recording reserves this many haptic ticks up front (the haptic thread then never allocates); a longer
  /// one still works, at the cost of one copy of the buffer when it grows.
  std::size_t record_reserve_ticks = 180000;
  /// While paused, the rest of the picture (overlays) is refreshed at this interval, s.
  double paused_refresh_s = 0.1;
};

class LiveSession {
 public:
  /// Builds the scene's simulation on the calling thread (InputError or NumericalError propagate: the CLI's
  /// exit codes) and shows its rest state. `device` is the interactive device; it and `observer` must outlive
  /// the session.
  LiveSession(const Scene& scene, Device& device, LiveObserver& observer, const LiveOptions& options = {});
  ~LiveSession();
  LiveSession(const LiveSession&) = delete;
  LiveSession& operator=(const LiveSession&) = delete;

  /// Realtime: starts the simulation thread (and the haptic loop). stop() joins both; the destructor too.
  void start();
  void stop();
  /// Lockstep: applies the posted commands and steps one frame on this thread (nothing when paused).
  void step_lockstep();

  // Commands from the UI thread (any thread): they never wait for the simulation.
  void set_paused(bool paused) { paused_.store(paused, std::memory_order_relaxed); }
  bool paused() const { return paused_.load(std::memory_order_relaxed); }
  /// One frame while paused.
  void step_once() { steps_requested_.fetch_add(1, std::memory_order_relaxed); }
  void post(LiveCommand command) { mailbox_.post(std::move(command)); }

 private:
  void run();
  void apply(const LiveCommand& command);
  void build(const Scene& scene, const LiveCommand::Kind kind, const std::filesystem::path& file);
  void attach_device(const LiveCommand::Kind kind, const std::filesystem::path& file);
  void write_recording(const std::filesystem::path& file);
  bool step_frame();
  void publish();
  void stop_rig();

  Device& interactive_;
  LiveObserver& observer_;
  LiveOptions options_;
  // Simulation thread only.
  Scene scene_;
  std::unique_ptr<Simulation> simulation_;
  DeviceDrivenModel* model_ = nullptr;
  std::optional<std::size_t> tool_;
  std::unique_ptr<ScriptedDevice> scripted_;
  std::unique_ptr<HapticRig> rig_;
  LiveFrameInfo info_;
  RealtimeClock clock_;
  std::size_t next_tick_ = 0;          // lockstep
  std::vector<double> recent_frames_;  // wall times of the frames in the last second
  int diverged_frames_ = 0;            // frames in a row above the divergence residual
  // Shared with the UI thread.
  std::atomic<bool> paused_{false}, stop_{false};
  std::atomic<int> steps_requested_{0};
  CommandMailbox mailbox_;
  std::thread thread_;
};

}  // namespace vascsim
