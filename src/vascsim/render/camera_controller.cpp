#include "vascsim/render/camera_controller.hpp"

namespace vascsim::render {

bool CameraController::button(MouseButton b, bool pressed, bool shift, bool ctrl) {
  if (!pressed) {
    if (drag_ != Drag::none && b == drag_button_) {
      drag_ = Drag::none;
      return true;
    }
    return false;
  }
  if (drag_ != Drag::none) return false;
  if (b == MouseButton::left && ctrl) return false;  // the tool's
  drag_ = (b == MouseButton::left && !shift) ? Drag::orbit : Drag::pan;
  drag_button_ = b;
  have_cursor_ = false;
  return true;
}

bool CameraController::cursor(double x, double y, int viewport_height_px) {
  const double dx = x - last_x_, dy = y - last_y_;
  const bool had = have_cursor_;
  last_x_ = x;
  last_y_ = y;
  have_cursor_ = true;
  if (drag_ == Drag::none || !had) return false;
  if (drag_ == Drag::orbit)
    camera_.orbit(dx, dy);
  else
    camera_.pan(dx, dy, viewport_height_px);
  return true;
}

bool CameraController::scroll(double notches) {
  camera_.zoom(notches);
  return true;
}

bool CameraController::key(int k) {
  if (k == 'R' || k == kHome) {
    camera_.reset();
    return true;
  }
  return false;
}

}  // namespace vascsim::render
