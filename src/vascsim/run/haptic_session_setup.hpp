#pragma once
// What a haptic session builds before its first tick, with every check it makes: the inputs it plays (the
// device's trajectory or a recording), the simulation, the model a device drives, the device and the rig.
// run_haptic_session builds it and then ticks; `vascsim check` builds the same and stops there, so it fails
// where the session would, with the same message.

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "vascsim/interaction/scripted_device.hpp"
#include "vascsim/interaction/trajectory.hpp"
#include "vascsim/run/haptic_rig.hpp"
#include "vascsim/run/haptic_session.hpp"
#include "vascsim/run/simulation.hpp"

namespace vascsim {

/// What a session plays: the device's trajectory (or a recording), read and checked before the slow set-up.
struct SessionInputs {
  std::size_t tool = 0;  ///< index into the scene's obstacles
  std::string mode;      ///< "lockstep" or "realtime"
  Trajectory trajectory;
  std::vector<ForceSample> recorded_forces;  ///< when replaying
  double duration_s = 0.0;
};

/// Reads and checks the session's inputs. Throws InputError naming the scene and key, or the device file.
SessionInputs read_session_inputs(const Scene& scene, const HapticRunOptions& options);

class SessionSetup {
 public:
  /// Reads the inputs, builds the simulation (with options.checks), the device-driven model (lockstep needs
  /// whole ticks per frame), the device and the rig. Throws InputError / NumericalError as the session would.
  SessionSetup(const Scene& scene, const HapticRunOptions& options);

  const SessionInputs& inputs() const { return inputs_; }
  Simulation& simulation() { return *simulation_; }
  DeviceDrivenModel& model() { return *model_; }
  HapticRig& rig() { return *rig_; }
  /// Haptic ticks the session makes (duration x rate, both ends included).
  std::size_t ticks() const { return ticks_; }
  /// Model frames the session steps.
  double frames() const;

 private:
  SessionInputs inputs_;
  std::size_t ticks_ = 0;
  std::unique_ptr<Simulation> simulation_;
  DeviceDrivenModel* model_ = nullptr;
  std::unique_ptr<ScriptedDevice> scripted_;
  Device* device_ = nullptr;
  std::unique_ptr<HapticRig> rig_;
};

}  // namespace vascsim
