// UNTESTED HERE (no SDK, no device on the development machine); see the header.
#include "vascsim/interaction/openhaptics_device.hpp"

#include <HD/hd.h>
#include <fmt/format.h>

#include <Eigen/Core>
#include <atomic>
#include <cmath>
#include <mutex>

#include "vascsim/core/error.hpp"

namespace vascsim {

namespace {
constexpr double kMetresPerMillimetre = 1e-3;
}  // namespace

struct OpenHapticsDevice::State {
  HHD handle = HD_INVALID_HANDLE;
  HDSchedulerHandle servo = 0;
  bool scheduled = false, scheduler_started = false;
  DeviceLimits limits;

  std::mutex mutex;                   // guards `pose` and `force_n` between the two threads
  DevicePose pose;                    // written by the servo thread
  Vec3 force_n = Vec3::Zero();        // written by the caller's haptic thread
  Vec3 servo_force_n = Vec3::Zero();  // servo thread only: its last output, reused on contention

  std::atomic<HDerror> error{HD_SUCCESS};  // last servo-loop error code
};

namespace {

// The servo callback, run by the SDK's scheduler at about 1 kHz. It must never block.
HDCallbackCode HDCALLBACK servo_tick(void* user) {
  auto& s = *static_cast<OpenHapticsDevice::State*>(user);
  hdBeginFrame(s.handle);
  HDdouble transform[16];  // column-major 4x4, translation in mm
  hdGetDoublev(HD_CURRENT_TRANSFORM, transform);
  HDint buttons = 0;
  hdGetIntegerv(HD_CURRENT_BUTTONS, &buttons);

  const Eigen::Map<const Eigen::Matrix4d> m(transform);
  DevicePose p;
  p.position_m = m.block<3, 1>(0, 3) * kMetresPerMillimetre;
  p.orientation = Eigen::Quaterniond(Mat3(m.block<3, 3>(0, 0))).normalized();
  p.buttons = static_cast<std::uint32_t>(buttons);

  std::unique_lock lock(s.mutex, std::try_to_lock);
  if (lock.owns_lock()) {
    s.pose = p;
    s.servo_force_n = s.force_n;
    lock.unlock();
  }
  const HDdouble force[3] = {s.servo_force_n.x(), s.servo_force_n.y(), s.servo_force_n.z()};
  hdSetDoublev(HD_CURRENT_FORCE, force);
  hdEndFrame(s.handle);

  const HDErrorInfo e = hdGetError();
  if (HD_DEVICE_ERROR(e)) s.error.store(e.errorCode);
  return HD_CALLBACK_CONTINUE;
}

[[noreturn]] void fail(const std::string& device, const char* step, const HDErrorInfo& e) {
  throw InputError(fmt::format(
      "OpenHaptics device '{}': {} failed: {} (code {}, internal {}); check the driver set-up (Touch Setup) "
      "and "
      "the device name",
      device, step, hdGetErrorString(e.errorCode), static_cast<int>(e.errorCode), e.internalErrorCode));
}

}  // namespace

OpenHapticsDevice::OpenHapticsDevice(const std::string& device_name) : state_(std::make_unique<State>()) {
  const std::string shown = device_name.empty() ? "(default)" : device_name;
  State& s = *state_;
  s.handle = hdInitDevice(device_name.empty() ? HD_DEFAULT_DEVICE : device_name.c_str());
  if (HDErrorInfo e = hdGetError(); HD_DEVICE_ERROR(e)) fail(shown, "hdInitDevice", e);
  hdMakeCurrentDevice(s.handle);

  // The driver's nominal values replace the Omni defaults (stiffness comes in N/mm, workspace in mm).
  HDdouble value = 0.0;
  hdGetDoublev(HD_NOMINAL_MAX_CONTINUOUS_FORCE, &value);
  if (value > 0.0) s.limits.max_continuous_force_n = value;
  hdGetDoublev(HD_NOMINAL_MAX_FORCE, &value);
  if (value > 0.0) s.limits.max_peak_force_n = value;
  hdGetDoublev(HD_NOMINAL_MAX_STIFFNESS, &value);
  if (value > 0.0) s.limits.max_stiffness_n_per_m = value * 1e3;
  HDdouble box[6] = {0, 0, 0, 0, 0, 0};  // min x, y, z, max x, y, z
  hdGetDoublev(HD_USABLE_WORKSPACE_DIMENSIONS, box);
  const Vec3 lo(box[0], box[1], box[2]), hi(box[3], box[4], box[5]);
  if ((hi - lo).minCoeff() > 0.0) {
    s.limits.workspace_center_m = 0.5 * (lo + hi) * kMetresPerMillimetre;
    s.limits.workspace_radius_m = 0.5 * (hi - lo).minCoeff() * kMetresPerMillimetre;  // inscribed sphere
  }

  hdEnable(HD_FORCE_OUTPUT);
  s.servo = hdScheduleAsynchronous(servo_tick, &s, HD_MAX_SCHEDULER_PRIORITY);
  s.scheduled = true;
  hdStartScheduler();
  if (HDErrorInfo e = hdGetError(); HD_DEVICE_ERROR(e)) {
    hdDisable(HD_FORCE_OUTPUT);
    hdUnschedule(s.servo);
    hdDisableDevice(s.handle);
    fail(shown, "starting the servo scheduler", e);
  }
  s.scheduler_started = true;
}

OpenHapticsDevice::~OpenHapticsDevice() {
  State& s = *state_;
  {
    const std::lock_guard lock(s.mutex);
    s.force_n = Vec3::Zero();
  }
  // Forces off first, so that the motors are never left holding the last command.
  hdMakeCurrentDevice(s.handle);
  hdDisable(HD_FORCE_OUTPUT);
  if (s.scheduler_started) hdStopScheduler();
  if (s.scheduled) hdUnschedule(s.servo);
  hdDisableDevice(s.handle);
}

const DeviceLimits& OpenHapticsDevice::limits() const {
  return state_->limits;
}

DevicePose OpenHapticsDevice::pose(double time_s) {
  DevicePose p;
  {
    const std::lock_guard lock(state_->mutex);
    p = state_->pose;
  }
  p.time_s = time_s;
  return p;
}

void OpenHapticsDevice::send_force(const Vec3& force_n, double /*time_s*/) {
  Vec3 f = force_n.allFinite() ? force_n : Vec3::Zero();
  const double peak = state_->limits.max_peak_force_n;
  if (const double n = f.norm(); n > peak) f *= peak / n;
  const std::lock_guard lock(state_->mutex);
  state_->force_n = f;
}

Vec3 OpenHapticsDevice::last_sent_force() const {
  const std::lock_guard lock(state_->mutex);
  return state_->force_n;
}

std::string OpenHapticsDevice::last_error() const {
  const HDerror e = state_->error.load();
  return e == HD_SUCCESS ? std::string() : std::string(hdGetErrorString(e));
}

}  // namespace vascsim
