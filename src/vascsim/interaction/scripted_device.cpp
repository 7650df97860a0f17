#include "vascsim/interaction/scripted_device.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vascsim {

namespace {
// Reserve the force log for the haptic rate over the trajectory plus a margin, but keep a very long
// trajectory from claiming memory up front (32 MiB at most; beyond that the log grows by doubling).
constexpr double kHapticRateHz = 1000.0;
constexpr double kMarginS = 1.0;
constexpr std::size_t kMaxReserved = std::size_t{1} << 20;
}  // namespace

ScriptedDevice::ScriptedDevice(Trajectory trajectory, DeviceLimits limits)
    : trajectory_(std::move(trajectory)), limits_(limits) {
  if (trajectory_.empty()) throw std::invalid_argument("ScriptedDevice: the trajectory is empty");
  const double ticks =
      std::ceil((trajectory_.end_time_s() - trajectory_.start_time_s() + kMarginS) * kHapticRateHz);
  sent_.reserve(static_cast<std::size_t>(std::min(ticks, static_cast<double>(kMaxReserved))));
}

DevicePose ScriptedDevice::pose(double time_s) {
  return trajectory_.at(time_s);
}

void ScriptedDevice::send_force(const Vec3& force_n, double time_s) {
  sent_.push_back({time_s, force_n});
  last_force_n_ = force_n;
}

}  // namespace vascsim
