#pragma once
// The scene's tools and the contact force as the renderer draws them (capsules and an arrow): the tool a
// device drives at the pose of the frame, any other tool where the load factor puts it. A catheter is drawn
// as its rigid part (rounded tip and short shaft, what the model simulates) continued by a display-only
// shaft, so it reads as a catheter coming from outside the picture; the display shaft is not in the
// simulation.

#include <cstddef>
#include <optional>

#include "vascsim/render/render_frame.hpp"
#include "vascsim/run/live_session.hpp"

namespace vascsim::viewer {

struct ToolStyle {
  double shaft_extension_m = 0.0;  ///< display shaft behind a catheter's rigid part, m
  render::Float3 colour = render::Float3(0.30f, 0.62f, 0.86f);  ///< a blue polymer catheter
};

/// frame.tools for the scene's obstacles; `driven`: the index of the tool the device poses (info's pose).
void fill_tools(const Scene& scene, std::optional<std::size_t> driven, const LiveFrameInfo& info,
                double load_factor, const ToolStyle& style, render::RenderFrame& frame);

/// frame.force: the force the driven tool exerts on the tissue, from the tool point; none without a tool.
void fill_force_arrow(const LiveFrameInfo& info, double threshold_n, render::RenderFrame& frame);

/// The safety threshold of a scene: viewer.force_threshold_n, else the force at which the device clamps
/// (haptics.force_limit_n / haptics.force_scale), N.
double force_threshold_n(const Scene& scene);

}  // namespace vascsim::viewer
