#pragma once
// The heads-up display and control panel (Dear ImGui 1.86). It shows the statistics it is given in a
// plain struct and reports what the user asked for in plain structs: it knows nothing of the simulation.
// The caller (the viewer) fills HudStats every frame, keeps one HudControls (the panel edits it in
// place: view mode, C-arm angles, overlays, material values) and acts on the one-shot HudRequests.
//
// One Hud at a time (ImGui has one global context). With a window context it installs ImGui's GLFW
// input callbacks, chained to any callbacks installed before it; headless it draws without input, so a
// screenshot can include the panel.

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "vascsim/core/json_reader.hpp"
#include "vascsim/render/render_frame.hpp"
#include "vascsim/render/renderer.hpp"

namespace vascsim::render {

class GlContext;

struct HudStats {
  std::string scene_name, model_name, device;  ///< device: what drives the tool ("" : no tool)
  double visual_fps = 0.0;
  double deformation_steps_per_s = 0.0;
  double haptic_rate_hz = 0.0;
  double haptic_p99_jitter_us = 0.0;
  double tool_force_n = 0.0;  ///< |force on the tool|
  double device_force_n =
      std::numeric_limits<double>::quiet_NaN();  ///< |force sent to the device|; NaN: unknown
  /// How far the model's tool was from the device pose its last frame was given, m; NaN: unknown.
  double tool_lag_m = std::numeric_limits<double>::quiet_NaN();
  /// Mean age of the frames the device's force came from (device pose to the tick that used it), ms; NaN:
  /// unknown.
  double force_age_ms = std::numeric_limits<double>::quiet_NaN();
  double force_threshold_n = 0.0;      ///< safety threshold (0: none); the force turns red above it
  std::vector<float> force_history_n;  ///< oldest first, plotted
  std::size_t nodes = 0, triangles = 0;
  double solver_residual = std::numeric_limits<double>::quiet_NaN();  ///< NaN: not reported
  double sim_time_s = 0.0;
  double simulation_ms = 0.0, map_ms = 0.0,
         normals_ms = 0.0;                ///< the simulation side's split of its last frame
  double upload_ms = 0.0, draw_ms = 0.0;  ///< the renderer's split of the last frame
  bool paused = false, recording = false;
  std::string message;  ///< the latest notice or error ("" : none)
  std::string gl_renderer;
};

/// The HUD's line on what the hand gets: the force sent to the device beside the model's tool force, how far
/// the model's tool is behind the hand and how old the force is ("" without a device or a known sent force).
std::string hand_line(const HudStats& stats);

enum class ColourField { none, displacement, stress };

/// Persistent panel state, edited in place by Hud::draw.
struct HudControls {
  ViewMode mode = ViewMode::lit;
  float carm_lao_deg = 0.0f, carm_cranial_deg = 0.0f;
  bool contrast_filled = true;
  /// Fluoroscopy: the monitor's window, a scale on every attenuation coefficient (1: physical). A 0.16 mm
  /// retinal artery attenuates 4 %, an aorta's lumen almost all: a window makes either readable.
  float fluoro_window = 1.0f;
  bool show_tools = true, show_force = true, show_nodes = false, show_tets = false, cutaway = false;
  ColourField colour_field = ColourField::none;
  float force_threshold_n = 0.0f;  ///< 0: the scene's
  std::vector<std::string> scene_choices, model_choices;
  std::string scene;  ///< the chosen scene (path)
  std::string model;  ///< the chosen model name
  double youngs_modulus_pa = 0.5e6, poisson_ratio = 0.45;
  std::vector<JsonField>
      model_settings;     ///< the model's settings block, as its reader took it (edited in place)
  std::string overrides;  ///< more "key=value" overrides, separated by spaces
  bool paused = false;
  bool recording = false;
  bool has_trajectory = false;  ///< the scene has a scripted trajectory to play
  std::string record_path = "session.csv";
  std::string replay_path;
};

/// What the user asked for this frame (one-shot).
struct HudRequests {
  bool toggle_pause = false, step = false, reset_simulation = false, reset_camera = false, screenshot = false;
  bool load_scene = false;      ///< HudControls::scene was chosen
  bool change_model = false;    ///< HudControls::model was chosen
  bool apply_settings = false;  ///< rebuild with the edited E, nu, model settings and overrides
  bool toggle_recording = false, start_replay = false, play_trajectory = false;
  bool any() const;
};

class Hud {
 public:
  explicit Hud(GlContext& context);
  ~Hud();
  Hud(const Hud&) = delete;
  Hud& operator=(const Hud&) = delete;

  /// Starts an ImGui frame (framebuffer size in pixels, seconds since the last frame).
  void begin_frame(int width, int height, double dt_s);
  /// Builds the panel; `legend` (may be null) adds the colour-map legend.
  HudRequests draw(const HudStats& stats, HudControls& controls, const ScalarField* legend);
  /// Renders the panel into the bound framebuffer (after the scene).
  void render();
  /// The panel has the mouse or the keyboard: do not pass the event to the camera or the tool.
  bool wants_mouse() const;
  bool wants_keyboard() const;

 private:
  bool glfw_ = false;
};

/// RenderSettings fields that the panel controls.
void apply_controls(const HudControls& controls, RenderSettings& settings);

}  // namespace vascsim::render
