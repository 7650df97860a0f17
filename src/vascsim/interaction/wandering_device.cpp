#include "vascsim/interaction/wandering_device.hpp"

#include <fmt/format.h>
#include <cmath>
#include <numbers>

#include "vascsim/core/error.hpp"

namespace vascsim {

namespace {

// SplitMix64 (Steele, Lea and Flood 2014): a well-mixed 64-bit hash, here of (seed, waypoint, axis).
std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// Uniform in [0, 1).
double uniform(std::uint64_t seed, std::uint64_t k, std::uint64_t axis) {
  const std::uint64_t h = splitmix64(splitmix64(splitmix64(seed) ^ k) ^ axis);
  return static_cast<double>(h >> 11) * 0x1.0p-53;
}

}  // namespace

WanderingDevice::WanderingDevice(const DevicePose& start, const WanderingBounds& bounds, DeviceLimits limits)
    : start_(start), bounds_(bounds), limits_(limits) {
  if (!(std::isfinite(bounds.depth_m) && bounds.depth_m >= 0.0 && std::isfinite(bounds.lateral_m) &&
        bounds.lateral_m >= 0.0 && std::isfinite(bounds.segment_s) && bounds.segment_s > 0.0))
    throw InputError(
        fmt::format("wandering device: depth_m = {} and lateral_m = {} must be finite and >= 0, "
                    "segment_s = {} finite and > 0",
                    bounds.depth_m, bounds.lateral_m, bounds.segment_s));
  axis_ = start.orientation * Vec3(0.0, 0.0, -1.0);  // the tool points along its local -z (device.hpp)
  across_1_ = start.orientation * Vec3::UnitX();
  across_2_ = start.orientation * Vec3::UnitY();
}

Vec3 WanderingDevice::waypoint(std::uint64_t k) const {
  if (k == 0) return start_.position_m;
  const double depth = bounds_.depth_m * uniform(bounds_.seed, k, 0);
  const double a = bounds_.lateral_m * (2.0 * uniform(bounds_.seed, k, 1) - 1.0);
  const double b = bounds_.lateral_m * (2.0 * uniform(bounds_.seed, k, 2) - 1.0);
  return start_.position_m + depth * axis_ + a * across_1_ + b * across_2_;
}

DevicePose WanderingDevice::pose(double time_s) {
  DevicePose p = start_;
  p.time_s = time_s;
  const double t = std::max(0.0, time_s - start_.time_s) / bounds_.segment_s;
  const double k = std::floor(t);
  const double ease = 0.5 - 0.5 * std::cos(std::numbers::pi * (t - k));  // 0 -> 1, zero slope at both ends
  const auto i = static_cast<std::uint64_t>(k);
  p.position_m = (1.0 - ease) * waypoint(i) + ease * waypoint(i + 1);
  return p;
}

}  // namespace vascsim
