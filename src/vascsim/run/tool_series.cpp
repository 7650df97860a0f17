#include "vascsim/run/tool_series.hpp"

#include "vascsim/geometry/capsule_surface.hpp"
#include "vascsim/geometry/vertex_normals.hpp"

namespace vascsim {

ToolSeries::ToolSeries(const OutputWriter& out, const Scene& scene, bool enabled)
    : scene_(scene), active_(enabled && !scene.obstacles.empty()), series_(out.series("tools")) {}

void ToolSeries::add(double stamp, const std::string& file_name,
                     const std::vector<constraints::Capsule>& placed) {
  if (!active_) return;
  RenderSurface surface;
  for (std::size_t o = 0; o < placed.size() && o < scene_.obstacles.size(); ++o)
    append_surface(surface, capsule_surface(placed[o].a, placed[o].b, scene_.obstacles[o].radius_m));
  if (first_.size() != surface.rest_vertices.size()) first_ = surface.rest_vertices;
  SurfaceFrame frame;
  frame.positions = surface.rest_vertices;
  frame.displacements.resize(frame.positions.size());
  for (std::size_t v = 0; v < frame.positions.size(); ++v)
    frame.displacements[v] = frame.positions[v] - first_[v];
  frame.normals = surface.rest_normals;
  series_.add_surface(stamp, file_name, frame, surface);
}

std::vector<constraints::Capsule> tools_at(const Scene& scene, double s) {
  std::vector<constraints::Capsule> placed;
  for (const RigidObstacle& o : scene.obstacles) placed.push_back(obstacle_at(o, s));
  return placed;
}

}  // namespace vascsim
