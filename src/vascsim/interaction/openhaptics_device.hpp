#pragma once
// A PHANTOM Omni / Geomagic Touch class device through the OpenHaptics HD API. This file is built only
// with -DVASCSIM_WITH_OPENHAPTICS=ON and the SDK installed (then VASCSIM_HAS_OPENHAPTICS is defined).
//
// UNTESTED HERE: there is neither a device nor the SDK on the development machine. The code follows the
// SDK's documented API: hdInitDevice, hdEnable(HD_FORCE_OUTPUT), an asynchronous servo callback
// (hdBeginFrame, hdGetDoublev(HD_CURRENT_TRANSFORM), hdSetDoublev(HD_CURRENT_FORCE), hdEndFrame),
// hdStartScheduler and hdGetError. It has only been compiled against stand-in declarations. Test it on
// real hardware before trusting it with a hand on the stylus.
//
// Units: the HD API reports millimetres; this class converts them to metres. Forces are in newtons in
// both. Positions are in the device's own frame, whose origin lies near the centre of the workspace:
// x right, y up, z towards the user. The controller maps that frame into the scene.
//
// Threads: the SDK runs the servo callback on its own 1 kHz scheduler thread. That thread and the
// caller's haptic thread share one small state (pose in, force out) under a mutex. The servo side only
// try_locks it, so it never waits: on contention it reuses the previous force and publishes the pose at
// its next tick. The caller's side holds the lock only to copy a pose or a force.

#include <memory>
#include <string>

#include "vascsim/interaction/device.hpp"

namespace vascsim {

class OpenHapticsDevice final : public Device {
 public:
  /// Opens `device_name` as configured in the driver's setup tool (empty: the default device),
  /// enables force output, and starts the servo loop. Limits come from the driver: nominal forces,
  /// stiffness, and the inscribed sphere of the usable workspace box. Throws InputError with the SDK's
  /// error text if the device cannot be opened.
  explicit OpenHapticsDevice(const std::string& device_name = "");
  /// Commands zero force, stops the scheduler and releases the device.
  ~OpenHapticsDevice() override;

  std::string_view name() const override { return "openhaptics"; }
  const DeviceLimits& limits() const override;
  /// The latest servo sample, stamped with `time_s`.
  DevicePose pose(double time_s) override;
  /// Safety guard, the one exception to "devices have no behaviour": a non-finite force becomes zero,
  /// and a force larger than max_peak_force_n is scaled down to it. The servo loop then outputs the
  /// result until the next call.
  void send_force(const Vec3& force_n, double time_s) override;
  Vec3 last_sent_force() const override;

  /// The last error reported by the servo loop ("" if none). For logs; it does not reset.
  std::string last_error() const;

  struct State;  // shared with the servo callback; defined in the .cpp

 private:
  std::unique_ptr<State> state_;
};

}  // namespace vascsim
