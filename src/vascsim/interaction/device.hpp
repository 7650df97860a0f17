#pragma once
// The haptic/input device interface. Following iMSTK's split, a device only reports its state (pose,
// buttons) and accepts a force; it has no behaviour. Virtual coupling, force clamping to the continuous
// limit, filtering and NaN guards belong to a controller that owns the device (written separately).

#include <Eigen/Geometry>
#include <cstdint>
#include <string_view>

#include "vascsim/core/types.hpp"

namespace vascsim {

/// One device state sample.
///
/// Frames: `position_m` and `orientation` are in the device's own frame, in metres. For the scripted
/// and mouse devices that frame is the scene frame; a hardware device reports its native frame and the
/// controller maps it into the scene. `orientation` rotates tool-frame vectors into that frame. Tool
/// frame convention (as OpenHaptics' stylus and OpenGL cameras): x right, y up, the tool points along
/// its local −z axis.
struct DevicePose {
  double time_s = 0.0;  ///< time at which this pose holds, on the caller's clock
  Vec3 position_m = Vec3::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< unit quaternion
  std::uint32_t buttons = 0;                                        ///< bit i set: button i pressed
};

/// One force command: the force sent to a device and the time it was sent.
struct ForceSample {
  double time_s = 0.0;
  Vec3 force_n = Vec3::Zero();
};

/// What a device can render and reach. Defaults: PHANTOM Omni class (Sensable / 3D Systems spec sheet
/// for the Omni: 3.3 N peak, 0.88 N continuous, stiffness 1.02-2.31 N/mm per axis, usable workspace
/// about 160 x 120 x 70 mm). All values are approximate and configurable; a hardware device replaces them
/// with what its driver reports.
struct DeviceLimits {
  /// Force the device can hold indefinitely; the controller's default clamp.
  double max_continuous_force_n = 0.88;
  /// Force the device can produce briefly; never exceed it.
  double max_peak_force_n = 3.3;
  /// Highest stiffness rendered without buzzing (the Omni's softest axis, 1.02 N/mm).
  double max_stiffness_n_per_m = 1000.0;
  /// The reachable workspace, modelled as a sphere in the device frame. 60 mm is half the Omni's
  /// 120 mm height: a round figure for a box-shaped workspace, so treat it as approximate.
  Vec3 workspace_center_m = Vec3::Zero();
  double workspace_radius_m = 0.06;
};

/// A device as the 1 kHz haptic thread sees it.
///
/// Real-time contract: `pose`, `send_force` and `last_sent_force` never block for long (at most they
/// hold a lock while copying a few values), never allocate once the device is set up, and never
/// throw. One thread (the haptic thread) calls them. If another thread also uses a device, that
/// device's header documents the hand-off.
///
/// Forces are in newtons, in the device frame. The caller is responsible for clamping them to
/// limits(). Hardware devices also refuse non-finite forces and cap at max_peak_force_n as a last
/// safety guard. Simulated devices store exactly what they receive, so tests can see what a
/// controller sent.
class Device {
 public:
  virtual ~Device() = default;
  Device() = default;
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  /// A short identifier for logs and summaries ("scripted", "mouse_keyboard", "openhaptics").
  virtual std::string_view name() const = 0;
  virtual const DeviceLimits& limits() const = 0;

  /// The device state at `time_s`, as seen by the caller. Simulated devices evaluate it at that time;
  /// hardware devices return the latest sample and stamp it with `time_s`.
  virtual DevicePose pose(double time_s) = 0;

  /// Commands `force_n` from `time_s` on, until the next call.
  virtual void send_force(const Vec3& force_n, double time_s) = 0;
  /// The force most recently commanded (zero before the first call): what send_force received, after
  /// a hardware device's safety guard.
  virtual Vec3 last_sent_force() const = 0;
};

}  // namespace vascsim
