#pragma once
// Cameras without GL: an orbit/pan/zoom camera for the lit view and the C-arm pose of the fluoroscopy
// view, both giving OpenGL view and projection matrices (column-major, right x up = -forward).
//
// Patient frame (anatomical, right-handed): `superior` towards the head, `anterior` towards the front of
// the body; the patient's right is anterior x superior. The vessel scenes lay their centre-lines along +z
// and bend towards +x in the x-z plane, so the defaults (superior +z, anterior +y) show those bends in
// the home (front) view.

#include <Eigen/Core>

#include "vascsim/interaction/mouse_keyboard_device.hpp"
#include "vascsim/render/render_frame.hpp"

namespace vascsim::render {

struct PatientFrame {
  Vec3 superior = Vec3::UnitZ();
  Vec3 anterior = Vec3::UnitY();
  Vec3 right() const { return anterior.cross(superior); }
};

struct CameraPose {
  Vec3 eye_m = Vec3(0, 1, 0);
  Vec3 target_m = Vec3::Zero();
  Vec3 up = Vec3::UnitZ();
  double fov_y_deg = 35.0;
  double near_m = 0.01, far_m = 10.0;
  /// Mirror the picture left-right (the C-arm view: projected from the source, seen from the detector).
  /// A mirrored projection flips the screen winding of triangles: draw with glFrontFace(GL_CW).
  bool mirror_x = false;

  Vec3 forward() const { return (target_m - eye_m).normalized(); }
  /// View matrix (world to eye), OpenGL convention.
  Eigen::Matrix4d view() const;
  /// Perspective projection for a viewport width / height.
  Eigen::Matrix4d projection(double aspect) const;
  /// The camera axes for the mouse/keyboard tool device: x to the right of the picture, y up, forward into
  /// the picture (for a mirrored pose: as seen from the detector).
  ViewFrame view_frame() const;
};

/// Orbit camera: the eye on a sphere around `target`. Orbit turns yaw about the patient's superior axis
/// and pitch towards it (clamped to +-85 degrees); pan moves the target in the view plane; zoom scales
/// the distance. reset() returns to the home view that frames the bounds given to fit().
class OrbitCamera {
 public:
  /// The C-arm's source distance in orbit distances (carm_pose).
  static constexpr double kCarmDistanceScale = 5.0;
  explicit OrbitCamera(const PatientFrame& patient = {}) : patient_(patient) {}

  /// Frames `bounds` (home view: from anterior, 15 degrees above) and resets to it.
  void fit(const Bounds& bounds);
  /// Keeps `bounds` between the near and far planes too (tools reaching out of the framed bounds), without
  /// changing the framing. fit() forgets it.
  void enclose(const Bounds& bounds);
  void reset();
  /// Cursor drag in pixels (x right, y down): 0.3 degree per pixel.
  void orbit(double dx_px, double dy_px);
  /// Cursor drag in pixels: the scene follows the cursor at the target's depth.
  void pan(double dx_px, double dy_px, int viewport_height_px);
  /// Scroll notches: positive zooms in (distance x 0.9 per notch), clamped to [0.02, 20] x home.
  void zoom(double notches);

  /// The lit view.
  CameraPose pose() const;
  /// The fluoroscopy view: the C-arm rotated `lao_deg` about the superior axis (positive: left anterior
  /// oblique, the detector towards the patient's left; negative: RAO) and tilted `cranial_deg` towards
  /// the head (negative: caudal). The centre of projection is the X-ray source, opposite the detector at
  /// kCarmDistanceScale times the orbit distance from the target with a field of view that frames the target
  /// as the orbit view does (zoom and pan apply): a nearly parallel projection with a magnification of about
  /// 1.2 across the scene, as a real C-arm's (source about 1 m from the detector), and a long catheter shaft
  /// never reaches the source. The picture is mirrored so it is seen from the detector, as on the C-arm's
  /// monitor: in AP the patient's right is on the left of the screen.
  CameraPose carm_pose(double lao_deg, double cranial_deg) const;

  double yaw_deg() const { return yaw_deg_; }
  double pitch_deg() const { return pitch_deg_; }
  double distance_m() const { return distance_m_; }
  const Vec3& target_m() const { return target_m_; }
  const PatientFrame& patient() const { return patient_; }
  double fov_y_deg() const { return fov_y_deg_; }

 private:
  CameraPose make_pose(const Vec3& direction_to_eye, double distance_scale) const;

  PatientFrame patient_;
  Bounds bounds_;
  Bounds clip_;  // bounds_ and what enclose() added
  double fov_y_deg_ = 35.0;
  double home_distance_m_ = 1.0;
  double yaw_deg_ = 0.0, pitch_deg_ = 15.0, distance_m_ = 1.0;
  Vec3 target_m_ = Vec3::Zero();
};

}  // namespace vascsim::render
