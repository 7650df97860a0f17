#include "vascsim/run/tool_reach.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <limits>

namespace vascsim {

namespace {

// The smallest gap between the capsule's surface and any node.
double clearance(const constraints::Capsule& capsule, const Vec3Array& nodes) {
  double best = std::numeric_limits<double>::infinity();
  for (const Vec3& p : nodes) best = std::min(best, obstacle_contact(capsule, p).value);
  return best;
}

// Samples so that consecutive ones are at most `step` apart over a distance `travel`.
int samples_for(double travel, double step) {
  return 1 + static_cast<int>(std::min(std::ceil(travel / step), 1e4));
}

}  // namespace

ToolReach tool_reach_by_load(const RigidObstacle& tool, const Vec3Array& nodes_m) {
  ToolReach r{tool.name, std::numeric_limits<double>::infinity(), 0.0, false};
  const int n = samples_for(tool.motion_m.norm(), 0.25 * tool.radius_m);
  for (int k = 0; k <= n - 1; ++k) {
    const double s = n > 1 ? static_cast<double>(k) / (n - 1) : 0.0;
    const double c = clearance(obstacle_at(tool, s), nodes_m);
    if (c < r.clearance_m) r.clearance_m = c, r.at = s;
  }
  return r;
}

ToolReach tool_reach_on_trajectory(const RigidObstacle& tool, const Trajectory& trajectory, double duration_s,
                                   const Vec3Array& nodes_m, bool first_contact) {
  ToolReach r{tool.name, std::numeric_limits<double>::infinity(), 0.0, true};
  const double t0 = trajectory.start_time_s(), t1 = t0 + duration_s;
  const double reach = std::max(tool.length_m, (tool.b_m - tool.a_m).norm()) + tool.radius_m;
  // The trajectory's own sample times within the session, and the session's ends.
  std::vector<double> times = {t0};
  for (const DevicePose& p : trajectory.samples())
    if (p.time_s > t0 && p.time_s < t1) times.push_back(p.time_s);
  times.push_back(t1);
  for (std::size_t i = 0; i + 1 < times.size(); ++i) {
    const DevicePose a = trajectory.at(times[i]), b = trajectory.at(times[i + 1]);
    const double travel =
        (b.position_m - a.position_m).norm() + reach * a.orientation.angularDistance(b.orientation);
    const int n = samples_for(travel, 0.25 * tool.radius_m);
    for (int k = 0; k < n; ++k) {
      const double t = times[i] + (times[i + 1] - times[i]) * k / n;
      const DevicePose p = trajectory.at(t);
      const double c = clearance(obstacle_posed(tool, p.position_m, p.orientation), nodes_m);
      if (c < r.clearance_m) r.clearance_m = c, r.at = t;
      if (first_contact && r.touches()) return r;
    }
  }
  const DevicePose end = trajectory.at(t1);
  const double c = clearance(obstacle_posed(tool, end.position_m, end.orientation), nodes_m);
  if (c < r.clearance_m) r.clearance_m = c, r.at = t1;
  return r;
}

std::string tool_reach_warning(const ToolReach& reach, const RigidObstacle& tool,
                               std::size_t obstacle_index) {
  const std::string where = reach.by_time ? fmt::format("at t = {:.3g} s of its trajectory", reach.at)
                                          : fmt::format("at load factor {:.3g}", reach.at);
  const char* keys = tool.catheter                                ? "tip_m and push_m"
                     : tool.shape == RigidObstacle::Shape::Sphere ? "centre_m and motion_m"
                                                                  : "a_m, b_m and motion_m";
  const std::string key = reach.by_time
                              ? std::string("the positions of the trajectory (haptics.device.trajectory, m)")
                              : fmt::format("obstacles.{}: {} (m)", obstacle_index, keys);
  return fmt::format(
      "tool '{}' will never touch the tissue: its path comes no closer than {:.4g} m to a node "
      "({}); check {}",
      reach.tool, reach.clearance_m, where, key);
}

}  // namespace vascsim
