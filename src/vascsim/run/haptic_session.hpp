#pragma once
// A haptic session (docs/haptics.md): the device poses a tool (the catheter) through the 1 kHz haptic
// loop while a device-driven model (model/device_driven_model.hpp: any model whose registry entry says so)
// deforms the tissue and publishes the contact force with its linearised response (contact_publisher.hpp).
//
//   device --pose--> HapticLoop (coupling, clamp, filter) --ToolPose--> model frame (contact)
//      ^                         |                                         |
//      +-------- force ----------+ <--------------- ContactState ----------+
//
// Two modes:
//  - lockstep: one thread; the loop ticks at the nominal times t0 + k/rate and the model steps every
//    ticks_per_step ticks with the pose of that tick. Deterministic: a recorded session replays bit for bit.
//  - realtime: the haptic loop on its own thread at wall-clock rate, the simulation on the calling thread
//    as fast as it can (never ahead of the wall clock); only the two LatestValue hand-offs are shared.
//
// Output folder: force_history.csv (one row per simulation step: the tool pose it used and the force the
// tissue exerts on the tool), haptic_ticks.csv (one row per tick: device and tool positions, the tissue's
// force on the tool at that tick, the force sent), session.csv (the recording, which --replay plays),
// summary.json with the loop statistics, and optionally the session recording and the surface series.

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>

#include "vascsim/interaction/device.hpp"
#include "vascsim/run/simulation.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim {

struct HapticRunOptions {
  std::filesystem::path out_dir;
  std::string mode;              ///< "" : the scene's; "lockstep" or "realtime" overrides it
  std::filesystem::path record;  ///< write the session recording here ("" : not written)
  std::filesystem::path replay;  ///< play this recording instead of the scene's trajectory
  /// A device of your own (e.g. OpenHapticsDevice, docs/haptics.md "Connecting a real device") instead of
  /// the scene's scripted one; it must outlive the call. Its poses are scene positions (m) and its limits
  /// cap the clamp. The session then lasts haptics.duration_s (required).
  Device* device = nullptr;
  /// false (soaks): no tick or frame is kept, so memory stays constant however long the session runs; no
  /// force_history.csv, session.csv or haptic_ticks.csv, and the frame statistics cover the newest 65,536
  /// frames.
  bool keep_ticks = true;
  /// Called now and then with (session time done, session length), s.
  std::function<void(double, double)> on_progress;
  /// Run while the simulation is built (e.g. a limit on the node count).
  BuildChecks checks;
  /// Called once the session is set up, before its first tick, with the simulation and the number of model
  /// frames the session will step (e.g. to estimate its cost, or refuse it by throwing).
  std::function<void(Simulation&, double frames)> after_setup;
};

/// Runs the session and returns summary.json's content (also written). Throws InputError for a scene
/// without a usable haptics block or tool, a model no device can drive, or bad device files.
nlohmann::json run_haptic_session(const Scene& scene, const HapticRunOptions& options);

/// The header of force_history.csv: per frame, the simulated time, the time of the pose it used, the tool
/// position (m), the force the tissue exerts on the tool (N) and its moment about the tool point (N m), the
/// contacts, the relative residual the frame reached and whether it converged, and the frame's wall time
/// (ms).
std::vector<std::string> force_history_columns();

}  // namespace vascsim
