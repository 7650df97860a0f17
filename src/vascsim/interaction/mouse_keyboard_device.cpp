#include "vascsim/interaction/mouse_keyboard_device.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vascsim {

namespace {

// A longer gap between two pose() calls (a paused loop, a debugger) is not integrated in full.
constexpr double kMaxKeyStepS = 0.1;

/// Re-orthonormalises `v`, keeping `forward` and the right-handed camera convention.
ViewFrame orthonormal(const ViewFrame& v) {
  const double fn = v.forward_m.norm();
  if (!(fn > 0.0) || !v.forward_m.allFinite())
    throw std::invalid_argument("ViewFrame: forward must be a finite non-zero vector");
  ViewFrame o;
  o.forward_m = v.forward_m / fn;
  const Vec3 r = v.right_m - v.right_m.dot(o.forward_m) * o.forward_m;
  if (!(r.norm() > 1e-9 * v.right_m.norm()) || !r.allFinite())
    throw std::invalid_argument("ViewFrame: right must be finite, non-zero and not parallel to forward");
  o.right_m = r.normalized();
  o.up_m = o.right_m.cross(o.forward_m);  // so that right x up = -forward
  if (!(v.up_m.dot(o.up_m) > 0.0))
    throw std::invalid_argument("ViewFrame: up must point along right x forward (right x up = -forward)");
  return o;
}

/// Tool frame to scene frame: x = right, y = up, z = -forward (the tool points along -z).
Eigen::Quaterniond tool_orientation(const ViewFrame& v) {
  Mat3 r;
  r.col(0) = v.right_m;
  r.col(1) = v.up_m;
  r.col(2) = -v.forward_m;
  return Eigen::Quaterniond(r).normalized();
}

/// The settings checked: the view re-orthonormalised, the orientation normalised.
MouseKeyboardSettings checked(MouseKeyboardSettings s) {
  s.view = orthonormal(s.view);
  if (s.orientation) {
    if (!(s.orientation->norm() > 0.0) || !s.orientation->coeffs().allFinite())
      throw std::invalid_argument(
          "MouseKeyboardSettings: the orientation must be a finite non-zero quaternion");
    s.orientation->normalize();
  }
  return s;
}

}  // namespace

MouseKeyboardDevice::MouseKeyboardDevice(const MouseKeyboardSettings& settings)
    : settings_(checked(settings)) {
  restart();
  last_pose_.position_m = position_m_;
  last_pose_.orientation = orientation_;
}

void MouseKeyboardDevice::restart() {
  position_m_ = settings_.limits.workspace_center_m;
  buttons_ = 0;
  insert_held_ = retract_held_ = twist_left_held_ = twist_right_held_ = false;
  follows_view_ = !settings_.orientation.has_value();
  orientation_ = follows_view_ ? tool_orientation(settings_.view) : *settings_.orientation;
}

void MouseKeyboardDevice::reconfigure(const MouseKeyboardSettings& settings) {
  MouseKeyboardSettings s = checked(settings);  // may throw: validate before locking
  const std::lock_guard lock(mutex_);
  s.view = settings_.view;  // the camera's, as set_view last gave it
  settings_ = s;
  restart();
}

Vec3 MouseKeyboardDevice::tool_axis() const {
  // Exactly the view's forward while the orientation follows the view.
  return follows_view_ ? settings_.view.forward_m : Vec3(orientation_ * (-Vec3::UnitZ()));
}

void MouseKeyboardDevice::turn(const Eigen::AngleAxisd& rotation) {
  orientation_ = (Eigen::Quaterniond(rotation) * orientation_).normalized();
  follows_view_ = false;
}

void MouseKeyboardDevice::move_clamped(const Vec3& delta_m) {
  // Clamp the stored position itself: moving back from the boundary responds at once.
  const Vec3& c = settings_.limits.workspace_center_m;
  const double r = settings_.limits.workspace_radius_m;
  Vec3 p = position_m_ + delta_m;
  const double d = (p - c).norm();
  if (d > r) p = c + (p - c) * (r / d);
  position_m_ = p;
}

DevicePose MouseKeyboardDevice::pose(double time_s) {
  std::unique_lock lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) {
    last_pose_.time_s = time_s;
    return last_pose_;
  }
  const double direction = (insert_held_ ? 1.0 : 0.0) - (retract_held_ ? 1.0 : 0.0);
  const double twist = (twist_right_held_ ? 1.0 : 0.0) - (twist_left_held_ ? 1.0 : 0.0);
  if (has_last_time_ && (direction != 0.0 || twist != 0.0)) {
    const double dt = std::clamp(time_s - last_time_s_, 0.0, kMaxKeyStepS);
    const Vec3 axis = tool_axis();
    if (direction != 0.0) move_clamped(direction * settings_.key_speed_m_per_s * dt * axis);
    if (twist != 0.0) turn(Eigen::AngleAxisd(twist * settings_.key_twist_rad_per_s * dt, axis));
  }
  last_time_s_ = time_s;
  has_last_time_ = true;
  last_pose_ = DevicePose{time_s, position_m_, orientation_, buttons_};
  return last_pose_;
}

void MouseKeyboardDevice::send_force(const Vec3& force_n, double /*time_s*/) {
  force_x_.store(force_n.x(), std::memory_order_relaxed);
  force_y_.store(force_n.y(), std::memory_order_relaxed);
  force_z_.store(force_n.z(), std::memory_order_relaxed);
}

Vec3 MouseKeyboardDevice::last_sent_force() const {
  return {force_x_.load(std::memory_order_relaxed), force_y_.load(std::memory_order_relaxed),
          force_z_.load(std::memory_order_relaxed)};
}

void MouseKeyboardDevice::move_cursor(double dx_px, double dy_px) {
  const std::lock_guard lock(mutex_);
  const ViewFrame& v = settings_.view;
  // Window y grows downwards, so a downward drag moves the tool down in the view.
  move_clamped(settings_.gain_m_per_pixel * (dx_px * v.right_m - dy_px * v.up_m));
}

void MouseKeyboardDevice::scroll(double notches) {
  const std::lock_guard lock(mutex_);
  move_clamped(settings_.scroll_step_m * notches * tool_axis());
}

void MouseKeyboardDevice::steer(double dx_px, double dy_px) {
  const std::lock_guard lock(mutex_);
  const ViewFrame& v = settings_.view;
  // Rotation vector axis x drag: the axis turns towards the drag's direction, by the drag's part across it.
  const Vec3 drag = dx_px * v.right_m - dy_px * v.up_m;
  const Vec3 w = settings_.steer_rad_per_pixel * tool_axis().cross(drag);
  const double angle = w.norm();
  if (angle > 0.0 && std::isfinite(angle)) turn(Eigen::AngleAxisd(angle, w / angle));
}

void MouseKeyboardDevice::set_key(ToolKey key, bool pressed) {
  const std::lock_guard lock(mutex_);
  switch (key) {
    case ToolKey::insert:
      insert_held_ = pressed;
      break;
    case ToolKey::retract:
      retract_held_ = pressed;
      break;
    case ToolKey::twist_left:
      twist_left_held_ = pressed;
      break;
    case ToolKey::twist_right:
      twist_right_held_ = pressed;
      break;
  }
  // The press time is unknown here: insertion starts counting from the next pose() call.
  if (pressed) has_last_time_ = false;
}

void MouseKeyboardDevice::set_button(int index, bool pressed) {
  if (index < 0 || index > 31) return;
  const std::lock_guard lock(mutex_);
  const std::uint32_t bit = std::uint32_t{1} << index;
  buttons_ = pressed ? (buttons_ | bit) : (buttons_ & ~bit);
}

void MouseKeyboardDevice::set_view(const ViewFrame& view) {
  const ViewFrame v = orthonormal(view);  // may throw: validate before locking
  const std::lock_guard lock(mutex_);
  settings_.view = v;
  if (follows_view_) orientation_ = tool_orientation(v);
}

void MouseKeyboardDevice::reset() {
  const std::lock_guard lock(mutex_);
  restart();
}

}  // namespace vascsim
