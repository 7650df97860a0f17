#pragma once
// A tool posed with the mouse and keyboard. This is a stand-in for a haptic device in the viewer, and
// it has no force output. Dragging moves the tool in the view plane. The scroll wheel, or two held
// keys, advance or retract it along its axis (the viewing direction, unless it was given or turned to
// an orientation of its own). Two more held keys twist it about its axis, and a steering drag turns its
// axis about the tool point. The tool stays inside the workspace sphere of limits().
// It has no windowing dependency: the viewer translates its GLFW events into the calls below.
//
// Threads: the input calls (move_cursor, scroll, set_key, set_button, set_view, reset) may run on the
// UI thread while pose() and send_force() run on the haptic thread. The input calls take a mutex to
// update the state. pose() only try_locks it: if the UI thread holds the lock, pose() returns the
// previous pose, so the haptic thread never waits. Input that arrives in the meantime is not lost:
// it is reported at the next tick.

#include <atomic>
#include <cstdint>
#include <mutex>
#include <optional>

#include "vascsim/interaction/device.hpp"

namespace vascsim {

/// The camera axes in the scene frame. The caller passes unit, mutually orthogonal vectors with
/// right x up = -forward, the OpenGL camera convention. They are re-orthonormalised, and degenerate
/// or left-handed input throws std::invalid_argument.
struct ViewFrame {
  Vec3 right_m = Vec3::UnitX();
  Vec3 up_m = Vec3::UnitY();
  Vec3 forward_m = -Vec3::UnitZ();
};

struct MouseKeyboardSettings {
  ViewFrame view;
  /// Tool displacement per pixel of cursor motion. 0.1 mm/px: a 600 px drag moves the tool 60 mm.
  double gain_m_per_pixel = 1e-4;
  /// Insertion per scroll notch (GLFW reports one notch as 1.0).
  double scroll_step_m = 1e-3;
  /// Insertion speed while the insert or retract key is held.
  double key_speed_m_per_s = 0.02;
  /// Twist about the tool's axis while a twist key is held, rad/s (about 86 degrees per second).
  double key_twist_rad_per_s = 1.5;
  /// Turn of the tool's axis per pixel of a steering drag, rad/px (0.3 degree per pixel).
  double steer_rad_per_pixel = 0.005236;
  /// The tool's orientation at the start (tool frame to scene, the tool pointing along its local -z).
  /// Unset: it points along the view (columns [right, up, -forward]) and follows set_view() until the
  /// first twist or steer.
  std::optional<Eigen::Quaterniond> orientation;
  /// Workspace sphere; the tool starts at its centre.
  DeviceLimits limits;
};

/// The keys the device understands. The viewer chooses which physical keys map to them. insert and
/// retract move the tool along its axis; twist_right turns it clockwise about its axis as seen from
/// behind (a positive turn about the axis), twist_left anticlockwise.
enum class ToolKey : std::uint8_t { insert, retract, twist_left, twist_right };

class MouseKeyboardDevice final : public Device {
 public:
  explicit MouseKeyboardDevice(const MouseKeyboardSettings& settings = {});

  std::string_view name() const override { return "mouse_keyboard"; }
  const DeviceLimits& limits() const override { return settings_.limits; }
  /// The current tool pose. If a key is held, it first advances the insertion by key_speed x
  /// (time_s - previous pose time), or the twist by key_twist x that time. A step is at most 0.1 s, so
  /// a pause does not make the tool jump. Motion starts at the first pose() call after a key press.
  /// Until the tool is turned (or given an orientation), the orientation has columns [right, up,
  /// -forward]: the tool points along the view direction.
  DevicePose pose(double time_s) override;
  /// There is no actuator: the force is only stored, so a heads-up display can show it.
  void send_force(const Vec3& force_n, double time_s) override;
  Vec3 last_sent_force() const override;

  /// A cursor move in window pixels: dx to the right, dy downwards (the GLFW convention). The tool
  /// moves gain x (dx right - dy up).
  void move_cursor(double dx_px, double dy_px);
  /// Scroll-wheel notches. Positive values insert the tool along its axis; negative values retract it.
  void scroll(double notches);
  /// A steering drag in window pixels (dx right, dy down): the tool's axis turns about the tool point
  /// towards the drag's direction on the screen, by steer_rad_per_pixel per pixel of the drag's part
  /// across the axis (a drag along the axis's own picture turns nothing). From then on the orientation
  /// no longer follows the view.
  void steer(double dx_px, double dy_px);
  void set_key(ToolKey key, bool pressed);
  /// Button `index` in [0, 31] becomes bit `index` of DevicePose::buttons; other indices are ignored.
  void set_button(int index, bool pressed);
  /// The camera moved. Later input follows the new axes; the tool position is unchanged, and so is its
  /// orientation unless it still follows the view.
  void set_view(const ViewFrame& view);
  /// Back to the workspace centre and the starting orientation, with no keys or buttons held.
  void reset();
  /// New settings (another scene's workspace, gains and starting orientation), then reset(); the view
  /// stays the one set_view() gave last. Throws std::invalid_argument for a bad orientation. limits()
  /// changes: not while a haptic loop polls the device.
  void reconfigure(const MouseKeyboardSettings& settings);

 private:
  void move_clamped(const Vec3& delta_m);        // caller holds mutex_
  Vec3 tool_axis() const;                        // caller holds mutex_: the direction the tool points
  void turn(const Eigen::AngleAxisd& rotation);  // caller holds mutex_
  void restart();                                // caller holds mutex_ (or constructs): back to the start

  MouseKeyboardSettings settings_;
  std::mutex mutex_;  // guards the input state below
  Vec3 position_m_;
  Eigen::Quaterniond orientation_;
  std::uint32_t buttons_ = 0;
  bool insert_held_ = false, retract_held_ = false, twist_left_held_ = false, twist_right_held_ = false;
  bool follows_view_ = true;  // the orientation is the view's until the first twist or steer
  double last_time_s_ = 0.0;
  bool has_last_time_ = false;

  DevicePose last_pose_;  // haptic thread only: returned when the lock is busy
  // Written by the haptic thread, read by the UI (HUD): one atomic per component, which is enough for a
  // display.
  std::atomic<double> force_x_{0.0}, force_y_{0.0}, force_z_{0.0};
};

}  // namespace vascsim
