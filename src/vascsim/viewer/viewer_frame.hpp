#pragma once
// What the simulation thread hands to the render thread in the viewer (through FrameExchange): the picture
// (RenderFrame: the MLS-mapped surface, tools, force arrow, overlays) and what the HUD shows about the
// simulation that produced it. Plain data, filled in place by FrameBuilder.

#include <cstddef>
#include <string>

#include "vascsim/render/render_frame.hpp"
#include "vascsim/run/live_session.hpp"

namespace vascsim::viewer {

/// The simulation side's cost of one frame, ms (wall clock on the simulation thread).
struct PrepareTiming {
  double simulation_ms = 0.0;  ///< the model's frame (pose, step, loads, contact publication)
  double map_ms = 0.0;         ///< MLS map of the node displacements to the surface (float)
  double normals_ms = 0.0;     ///< vertex normals of the deformed surface
  double fill_ms = 0.0;        ///< the rest: colour map, overlays, tools, statistics
};

struct ViewerFrame {
  render::RenderFrame render;
  LiveFrameInfo info;  ///< the session's report of this frame
  PrepareTiming timing;
  std::string scene_name, scene_file, model;
  std::size_t nodes = 0;
  double force_threshold_n = 0.0;  ///< the safety threshold the arrow and the HUD use, N
  double tool_force_n = 0.0;       ///< |force of the tool on the tissue|, N
};

}  // namespace vascsim::viewer
