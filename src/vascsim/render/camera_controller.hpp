#pragma once
// Mouse and keyboard to camera: left drag orbits, right or middle drag (or shift + left drag) pans, the
// wheel zooms, R or Home resets. Ctrl + left drag is left alone: the viewer gives it to the tool (the
// mouse/keyboard device). No windowing dependency: the viewer forwards its GLFW events, after asking the
// HUD whether it wants them.

#include "vascsim/render/camera.hpp"

namespace vascsim::render {

enum class MouseButton { left, right, middle };

class CameraController {
 public:
  explicit CameraController(OrbitCamera& camera) : camera_(camera) {}

  /// Returns true if the camera takes the press (then it also takes the drag until the release).
  bool button(MouseButton button, bool pressed, bool shift, bool ctrl);
  /// Cursor position in window pixels (y down). Returns true if it moved the camera.
  bool cursor(double x_px, double y_px, int viewport_height_px);
  /// Wheel notches (positive: away from the user, zooms in).
  bool scroll(double notches);
  /// 'R' or Home resets the camera. `key` is the character (upper case) or kHome.
  bool key(int key);
  static constexpr int kHome = 268;  // GLFW_KEY_HOME

  bool dragging() const { return drag_ != Drag::none; }

 private:
  enum class Drag { none, orbit, pan };
  OrbitCamera& camera_;
  Drag drag_ = Drag::none;
  MouseButton drag_button_ = MouseButton::left;
  bool have_cursor_ = false;
  double last_x_ = 0.0, last_y_ = 0.0;
};

}  // namespace vascsim::render
