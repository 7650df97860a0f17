#include "vascsim/viewer/frame_builder.hpp"

#include "vascsim/core/stopwatch.hpp"
#include "vascsim/viewer/mouse_workspace.hpp"

namespace vascsim::viewer {

FrameBuilder::FrameBuilder(FrameExchange<ViewerFrame>& exchange, MouseKeyboardDevice& mouse,
                           const OverlayRequests& overlays, bool skip_unseen)
    : exchange_(exchange), mouse_(mouse), overlays_(overlays), skip_unseen_(skip_unseen) {}

void FrameBuilder::built(Simulation& simulation, std::optional<std::size_t> tool) {
  surface_.rebuild(simulation, ++builds_);
  tool_ = tool;
  style_.shaft_extension_m = 1.5 * surface_.radius_m();
  if (tool)
    mouse_.reconfigure(mouse_settings(simulation.scene(), *tool, surface_.rest_min(), surface_.rest_max()));
}

void FrameBuilder::frame(Simulation& simulation, const LiveFrameInfo& info) {
  // The first frame of a build always goes out: the render thread must see the new topology.
  if (skip_unseen_ && exchange_.pending() && info.frame > 0) return;
  ViewerFrame& f = exchange_.back();
  if (!surface_.fill(simulation, f.render, f.timing)) return;  // a non-finite state is never drawn
  const Stopwatch clock;
  const Scene& scene = simulation.scene();
  f.info = info;
  f.timing.simulation_ms = 1e3 * info.sample.wall_s;
  f.scene_name = scene.name;
  f.scene_file = scene.file;
  f.model = scene.model;
  f.nodes = simulation.discretization().rest_positions().size();
  const double threshold = overlays_.force_threshold_n.load(std::memory_order_relaxed);
  f.force_threshold_n = threshold > 0.0 ? threshold : force_threshold_n(scene);
  f.tool_force_n = info.sample.force_n.norm();
  if (overlays_.stress.load(std::memory_order_relaxed)) surface_.fill_stress(simulation, f.render);
  surface_.fill_overlays(simulation, overlays_.nodes.load(std::memory_order_relaxed),
                         overlays_.tets.load(std::memory_order_relaxed), f.render);
  fill_tools(scene, tool_, info, simulation.model().load_factor(), style_, f.render);
  fill_force_arrow(info, f.force_threshold_n, f.render);
  f.render.sim_time_s = info.sample.sim_time_s;
  f.render.sequence = ++sequence_;
  f.timing.fill_ms = 1e3 * clock.seconds();
  exchange_.publish();
}

}  // namespace vascsim::viewer
