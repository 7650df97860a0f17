#pragma once
// The options of `vascsim view` (view_command.cpp parses them; docs/viewer.md).

#include <string>
#include <vector>

namespace vascsim::viewer {

struct ViewOptions {
  std::string scene;              ///< scene file
  std::vector<std::string> sets;  ///< --set key=value overrides
  // Headless pictures: --screenshot FILE renders --frames N frames without a display (EGL) and exits.
  std::string screenshot;
  std::string fluoro_screenshot;  ///< also the last frame as fluoroscopy (--lao, --cranial), headless
  int frames = 0;                 ///< 0: until the window closes (headless: 1)
  std::string size = "1280x800";  ///< window or picture size, WIDTHxHEIGHT pixels
  bool headless = false;          ///< EGL even with a display
  bool realtime = false;          ///< headless: the threads of a window session (timing), not lockstep frames
  bool measure = false;           ///< glFinish between phases; print the timing split at the end
  /// Visual frames per second at most (as a display's vsync would; software rendering shares the cores with
  /// the simulation). 0: as fast as it can (--measure's default).
  double max_fps = 60.0;
  bool paused = false;  ///< start paused (headless: the rest state)
  bool play = false;    ///< the scene's scripted trajectory drives the tool instead of the mouse
  std::string replay;   ///< a session recording drives the tool instead of the mouse
  bool hud = false;     ///< headless: draw the panel into the picture too
  // The view at the start (all also in the panel).
  std::string mode = "lit";  ///< lit or fluoro
  double lao_deg = 0.0, cranial_deg = 0.0;
  double fluoro_window = 0.0;  ///< attenuation scale of the fluoroscopy; 0: from the vessel's size
  double yaw_deg = 0.0, pitch_deg = 15.0, zoom = 0.0;
  bool cutaway = false, nodes = false, tets = false, colour_map = false, stress_map = false,
       no_contrast = false;
  bool no_surface = false;  ///< do not draw the wall (to check that the tests notice)
  int msaa = 0;
};

}  // namespace vascsim::viewer
