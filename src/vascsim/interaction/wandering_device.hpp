#pragma once
// A simulated device that wanders at random within bounds, for soak tests: from a start pose the tool moves
// to a new waypoint every segment_s (smoothly: cosine easing, so the velocity is continuous), each drawn
// uniformly from a box in the tool's frame: up to depth_m along the tool's axis (pushing in) and up to
// +-lateral_m across it. The waypoints are a hash of (seed, index): the motion is reproducible, nothing is
// stored, and memory is constant however long it runs. Orientation and buttons stay those of the start pose.

#include <cstdint>

#include "vascsim/interaction/device.hpp"

namespace vascsim {

struct WanderingBounds {
  double depth_m = 1.4e-3;  ///< along the tool's pointing direction (its local -z), from 0 to this, m
  double lateral_m = 1e-3;  ///< across it, +- this in both directions, m
  double segment_s = 0.5;   ///< time between waypoints, s
  std::uint64_t seed = 1;
};

class WanderingDevice final : public Device {
 public:
  /// Throws InputError for bounds that are negative, not finite, or a segment_s <= 0.
  WanderingDevice(const DevicePose& start, const WanderingBounds& bounds, DeviceLimits limits = {});

  std::string_view name() const override { return "wandering"; }
  const DeviceLimits& limits() const override { return limits_; }
  DevicePose pose(double time_s) override;
  void send_force(const Vec3& force_n, double) override { last_force_n_ = force_n; }
  Vec3 last_sent_force() const override { return last_force_n_; }

  /// Waypoint k (0: the start position), m.
  Vec3 waypoint(std::uint64_t k) const;

 private:
  DevicePose start_;
  WanderingBounds bounds_;
  DeviceLimits limits_;
  Vec3 axis_, across_1_, across_2_;  // the tool's pointing direction and two unit vectors across it
  Vec3 last_force_n_ = Vec3::Zero();
};

}  // namespace vascsim
