#pragma once
// A device that plays a Trajectory and records every force sent to it. It drives tests, experiments
// and the replay of recorded sessions. Its pose depends only on the queried time, so a run that uses it
// is as deterministic as the simulation itself.

#include <cstddef>
#include <string>
#include <vector>

#include "vascsim/interaction/device.hpp"
#include "vascsim/interaction/trajectory.hpp"

namespace vascsim {

class ScriptedDevice final : public Device {
 public:
  /// `trajectory` must not be empty. The force log is reserved for the trajectory's duration at
  /// 1 kHz (plus 1 s, capped at 2^20 entries), so a normal run allocates nothing in send_force.
  explicit ScriptedDevice(Trajectory trajectory, DeviceLimits limits = {});

  std::string_view name() const override { return "scripted"; }
  const DeviceLimits& limits() const override { return limits_; }
  /// trajectory().at(time_s).
  DevicePose pose(double time_s) override;
  /// Appends {time_s, force_n} to sent_forces(), unmodified (even NaN, so tests can catch it).
  void send_force(const Vec3& force_n, double time_s) override;
  Vec3 last_sent_force() const override { return last_force_n_; }

  const Trajectory& trajectory() const { return trajectory_; }
  /// Every force received, in call order. Read it after the haptic thread has stopped.
  const std::vector<ForceSample>& sent_forces() const { return sent_; }
  /// Makes room for `count` more force samples without allocation.
  void reserve_forces(std::size_t count) { sent_.reserve(sent_.size() + count); }

 private:
  Trajectory trajectory_;
  DeviceLimits limits_;
  std::vector<ForceSample> sent_;
  Vec3 last_force_n_ = Vec3::Zero();
};

}  // namespace vascsim
