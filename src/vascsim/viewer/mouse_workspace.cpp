#include "vascsim/viewer/mouse_workspace.hpp"

namespace vascsim::viewer {

MouseKeyboardSettings mouse_settings(const Scene& scene, std::size_t tool, double scene_radius_m) {
  const RigidObstacle& o = scene.obstacles.at(tool);
  MouseKeyboardSettings s;
  s.limits.workspace_center_m = o.tool_point_m;
  s.limits.workspace_radius_m = 2.0 * scene_radius_m;
  s.gain_m_per_pixel = scene_radius_m / 400.0;
  s.scroll_step_m = scene_radius_m / 40.0;
  s.key_speed_m_per_s = scene_radius_m / 4.0;
  // The rest pose: a catheter points along its axis towards the tip (tool frame -z); other tools' rest shape
  // is their identity pose (rigid_obstacle.hpp obstacle_posed).
  s.orientation = o.catheter ? orientation_pointing(o.a_m - o.b_m) : Eigen::Quaterniond::Identity();
  return s;
}

}  // namespace vascsim::viewer
