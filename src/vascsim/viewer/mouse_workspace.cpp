#include "vascsim/viewer/mouse_workspace.hpp"

#include <algorithm>

namespace vascsim::viewer {

MouseKeyboardSettings mouse_settings(const Scene& scene, std::size_t tool, const Vec3& lo, const Vec3& hi) {
  const RigidObstacle& o = scene.obstacles.at(tool);
  const double side = std::max((hi - lo).minCoeff(), 1e-9);
  MouseKeyboardSettings s;
  s.limits.workspace_center_m = o.tool_point_m;
  s.limits.workspace_radius_m = std::max((hi - lo).norm(), 1e-9);
  s.gain_m_per_pixel = side / 300.0;
  s.scroll_step_m = side / 30.0;
  s.key_speed_m_per_s = side / 3.0;
  // The rest pose: a catheter points along its axis towards the tip (tool frame -z); other tools' rest shape
  // is their identity pose (rigid_obstacle.hpp obstacle_posed).
  s.orientation = o.catheter ? orientation_pointing(o.a_m - o.b_m) : Eigen::Quaterniond::Identity();
  return s;
}

}  // namespace vascsim::viewer
