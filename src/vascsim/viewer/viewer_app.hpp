#pragma once
// `vascsim view`: a scene's model driven live with the mouse device (or a recording, or the scene's own
// trajectory) through the haptic loop, drawn in a GLFW window with the HUD and panel, or headless through EGL
// into a PNG (docs/viewer.md). Three threads in a window: this one (events, HUD, drawing), the simulation
// thread (run/live_session) and the haptic thread; headless pictures step the simulation in lockstep on this
// thread unless --realtime.

#include <ostream>

#include "vascsim/viewer/view_options.hpp"

namespace vascsim::viewer {

/// Runs the viewer; returns the exit code. Throws InputError (bad scene, size, texture file, no display and
/// no EGL: the CLI's exit code 2) or NumericalError (exit code 3) before anything is drawn.
int run_viewer(const ViewOptions& options, std::ostream& out);

}  // namespace vascsim::viewer
