#pragma once
// The viewer's window input (GLFW callbacks, on the render thread): what the HUD does not take goes to the
// camera, the tool (the mouse/keyboard device, which hands it to the haptic thread) or the viewer's keys.
//
//   left drag              orbit (lit); turn the C-arm (fluoroscopy: LAO/RAO across, cranial/caudal up-down)
//   right or middle drag   pan (also shift + left drag);  wheel: zoom;  R or Home: reset the camera
//   ctrl + left drag       push the tool in the view plane;  ctrl + right drag: steer the tool's axis
//   ctrl + wheel           advance (up) / retract (down) the tool
//   W / S, Up / Down       advance / retract the tool while held;  A / D, Left / Right: twist it while held
//   F fluoroscopy on/off   [ ] C-arm LAO -/+ 5 deg   PageUp/PageDown cranial/caudal 5 deg
//   space pause/run   N or . one step   Backspace or F5 reset the scene   C colour map   P or F12 screenshot
//   H hide/show the panel   Esc quit

#include "vascsim/interaction/mouse_keyboard_device.hpp"
#include "vascsim/render/camera_controller.hpp"
#include "vascsim/render/hud.hpp"

struct GLFWwindow;

namespace vascsim::viewer {

/// One-shot requests from the keyboard, taken once per frame.
struct KeyRequests {
  bool toggle_pause = false, step = false, reset_scene = false, screenshot = false, toggle_hud = false;
};

class WindowInput {
 public:
  /// Installs the callbacks on `window`; install it before the Hud (whose callbacks chain to these).
  /// `controls` is the panel state (view mode, C-arm angles, colour field) the keys edit. All must outlive
  /// the input.
  WindowInput(GLFWwindow* window, render::CameraController& camera, render::OrbitCamera& orbit,
              MouseKeyboardDevice& tool, render::HudControls& controls);
  void set_hud(const render::Hud* hud) { hud_ = hud; }
  /// The keyboard's requests since the last call.
  KeyRequests take();

  // The callbacks (public for the C trampolines).
  void on_button(int button, int action, int mods);
  void on_cursor(double x, double y);
  void on_scroll(double dy, bool ctrl);
  void on_key(int key, int action, int mods);

 private:
  enum class Drag { none, push, steer, carm };
  bool hud_has_mouse() const { return hud_ != nullptr && hud_->wants_mouse(); }
  bool tool_key(int key, bool pressed);

  GLFWwindow* window_;
  render::CameraController& camera_;
  render::OrbitCamera& orbit_;
  MouseKeyboardDevice& tool_;
  render::HudControls& controls_;
  const render::Hud* hud_ = nullptr;
  KeyRequests requests_;
  Drag drag_ = Drag::none;
  bool have_cursor_ = false;
  double last_x_ = 0.0, last_y_ = 0.0;
};

}  // namespace vascsim::viewer
