#pragma once
// Whether a rigid tool will touch the body, from the geometry alone, before anything is solved: the closest
// the tool's contact surface comes to a node along the path it will follow (its swept path from s = 0 to 1
// for a tool moved by the load factor; the device's trajectory in a haptic session). A tool whose position
// was typed in millimetres ends up metres away, and the run would otherwise only report zero force.

#include <string>
#include <vector>

#include "vascsim/interaction/trajectory.hpp"
#include "vascsim/model/rigid_obstacle.hpp"

namespace vascsim {

struct ToolReach {
  std::string tool;
  /// The smallest gap between the tool's contact surface (radius + node_radius_m) and a node along the path,
  /// m; <= 0: the tool reaches the tissue.
  double clearance_m = 0.0;
  /// Where on the path the gap is smallest: a load factor (by_time false) or a session time, s.
  double at = 0.0;
  bool by_time = false;
  bool touches() const { return clearance_m <= 0.0; }
};

/// A tool moved by the load factor: the capsule swept from s = 0 to s = 1, sampled at most a quarter of the
/// tool radius apart (so the gap is found to within that).
ToolReach tool_reach_by_load(const RigidObstacle& tool, const Vec3Array& nodes_m);

/// A tool posed by a device playing `trajectory` from its start for `duration_s`: the poses sampled so that
/// no point of the tool moves more than a quarter of its radius between samples. With `first_contact`, the
/// search ends at the first pose that reaches the tissue (enough for touches(); the deepest pass needs the
/// whole path).
ToolReach tool_reach_on_trajectory(const RigidObstacle& tool, const Trajectory& trajectory, double duration_s,
                                   const Vec3Array& nodes_m, bool first_contact = false);

/// One line for a tool that does not reach the tissue: the gap, where, and the scene key that places it.
std::string tool_reach_warning(const ToolReach& reach, const RigidObstacle& tool, std::size_t obstacle_index);

}  // namespace vascsim
