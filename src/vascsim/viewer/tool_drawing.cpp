#include "vascsim/viewer/tool_drawing.hpp"

namespace vascsim::viewer {

namespace {

render::ToolCapsule capsule_of(const RigidObstacle& tool, const constraints::Capsule& placed,
                               const ToolStyle& style) {
  render::ToolCapsule c;
  c.radius_m = static_cast<float>(tool.radius_m);
  c.colour = style.colour;
  Vec3 axis = placed.a - placed.b;                                                          // towards the tip
  if (axis.norm() < 1e-12 * (1.0 + placed.a.norm())) axis = Vec3::UnitZ() * tool.radius_m;  // a sphere
  const Vec3 d = axis.normalized();
  const double extension = tool.catheter ? style.shaft_extension_m : 0.0;
  c.tip_m = (placed.a + tool.radius_m * d).cast<float>();  // the rounded tip's apex
  c.back_m = (placed.b - (extension + (placed.a == placed.b ? tool.radius_m : 0.0)) * d).cast<float>();
  c.rounded_tip = true;
  return c;
}

}  // namespace

void fill_tools(const Scene& scene, std::optional<std::size_t> driven, const LiveFrameInfo& info,
                double load_factor, const ToolStyle& style, render::RenderFrame& frame) {
  frame.tools.clear();
  for (std::size_t o = 0; o < scene.obstacles.size(); ++o) {
    const RigidObstacle& tool = scene.obstacles[o];
    const constraints::Capsule placed =
        driven && *driven == o && info.has_tool
            ? obstacle_posed(tool, info.sample.tool_position_m, info.tool_orientation)
            : obstacle_at(tool, load_factor);
    frame.tools.push_back(capsule_of(tool, placed, style));
  }
}

void fill_force_arrow(const LiveFrameInfo& info, double threshold_n, render::RenderFrame& frame) {
  if (!info.has_tool) {
    frame.force.reset();
    return;
  }
  render::ForceArrow a;
  a.origin_m = info.sample.tool_position_m.cast<float>();
  a.force_n = (-info.sample.force_n).cast<float>();  // the tool's force on the tissue
  a.threshold_n = static_cast<float>(threshold_n);
  frame.force = a;
}

double force_threshold_n(const Scene& scene) {
  if (scene.viewer.force_threshold_n > 0.0) return scene.viewer.force_threshold_n;
  return scene.haptics.force_scale > 0.0 ? scene.haptics.force_limit_n / scene.haptics.force_scale
                                         : scene.haptics.force_limit_n;
}

}  // namespace vascsim::viewer
