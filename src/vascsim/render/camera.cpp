#include "vascsim/render/camera.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

namespace vascsim::render {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
}

Eigen::Matrix4d CameraPose::view() const {
  const Vec3 f = forward();
  const Vec3 r = f.cross(up).normalized();
  const Vec3 u = r.cross(f);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = r.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  m(0, 3) = -r.dot(eye_m);
  m(1, 3) = -u.dot(eye_m);
  m(2, 3) = f.dot(eye_m);
  return m;
}

Eigen::Matrix4d CameraPose::projection(double aspect) const {
  const double t = 1.0 / std::tan(0.5 * fov_y_deg * kDeg);
  Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
  p(0, 0) = t / aspect;
  p(1, 1) = t;
  p(2, 2) = -(far_m + near_m) / (far_m - near_m);
  p(2, 3) = -2.0 * far_m * near_m / (far_m - near_m);
  p(3, 2) = -1.0;
  if (mirror_x) p(0, 0) = -p(0, 0);
  return p;
}

ViewFrame CameraPose::view_frame() const {
  ViewFrame v;
  v.forward_m = forward();
  v.right_m = v.forward_m.cross(up).normalized();
  v.up_m = v.right_m.cross(v.forward_m);
  if (mirror_x) {
    // Seen from the other side: the picture's right is the camera's left, and forward reverses.
    v.right_m = -v.right_m;
    v.forward_m = -v.forward_m;
  }
  return v;
}

void OrbitCamera::fit(const Bounds& bounds) {
  bounds_ = bounds;
  clip_ = bounds;
  const double r = std::max(bounds.radius(), 1e-9);
  // The bounding sphere fits the vertical field of view with 5 % margin.
  home_distance_m_ = 1.05 * r / std::sin(0.5 * fov_y_deg_ * kDeg);
  reset();
}

void OrbitCamera::reset() {
  yaw_deg_ = 0.0;
  pitch_deg_ = 15.0;
  distance_m_ = home_distance_m_;
  target_m_ = bounds_.centre();
}

void OrbitCamera::orbit(double dx_px, double dy_px) {
  yaw_deg_ = std::remainder(yaw_deg_ - 0.3 * dx_px, 360.0);
  pitch_deg_ = std::clamp(pitch_deg_ + 0.3 * dy_px, -85.0, 85.0);
}

void OrbitCamera::pan(double dx_px, double dy_px, int viewport_height_px) {
  const CameraPose p = pose();
  const ViewFrame v = p.view_frame();
  const double metres_per_px =
      2.0 * distance_m_ * std::tan(0.5 * fov_y_deg_ * kDeg) / std::max(1, viewport_height_px);
  target_m_ += metres_per_px * (-dx_px * v.right_m + dy_px * v.up_m);
}

void OrbitCamera::zoom(double notches) {
  distance_m_ =
      std::clamp(distance_m_ * std::pow(0.9, notches), 0.02 * home_distance_m_, 20.0 * home_distance_m_);
}

void OrbitCamera::enclose(const Bounds& bounds) {
  clip_.min = clip_.min.cwiseMin(bounds.min);
  clip_.max = clip_.max.cwiseMax(bounds.max);
}

CameraPose OrbitCamera::make_pose(const Vec3& direction_to_eye, double distance_scale) const {
  CameraPose p;
  // Farther away by distance_scale with a field of view that frames the target's plane the same.
  p.fov_y_deg = 2.0 * std::atan(std::tan(0.5 * fov_y_deg_ * kDeg) / distance_scale) / kDeg;
  p.target_m = target_m_;
  p.eye_m = target_m_ + distance_scale * distance_m_ * direction_to_eye.normalized();
  // Up: the superior axis, unless the view looks along it (then anterior).
  const Vec3 s = patient_.superior.normalized();
  p.up = std::abs(direction_to_eye.normalized().dot(s)) < 0.999 ? s : patient_.anterior.normalized();
  // Near and far planes bracket the bounding sphere of what is drawn (at least 1e-3 of the distance in
  // front).
  const double r = std::max(clip_.radius(), 1e-9);
  const double d = (clip_.centre() - p.eye_m).norm();
  p.near_m = std::max(d - 1.5 * r, 1e-3 * distance_m_);
  p.far_m = std::max(d + 1.5 * r, 2.0 * p.near_m);
  return p;
}

CameraPose OrbitCamera::pose() const {
  const Vec3 s = patient_.superior.normalized();
  const Vec3 a = patient_.anterior.normalized();
  const Vec3 r = a.cross(s);  // patient's right
  const double yaw = yaw_deg_ * kDeg, pitch = pitch_deg_ * kDeg;
  // Yaw 0: from anterior; positive yaw moves the eye towards the patient's right.
  const Vec3 dir = std::cos(pitch) * (std::cos(yaw) * a + std::sin(yaw) * r) + std::sin(pitch) * s;
  return make_pose(dir, 1.0);
}

CameraPose OrbitCamera::carm_pose(double lao_deg, double cranial_deg) const {
  const Vec3 s = patient_.superior.normalized();
  const Vec3 a = patient_.anterior.normalized();
  const Vec3 left = -a.cross(s);
  const double lao = lao_deg * kDeg, cra = cranial_deg * kDeg;
  // The detector over the patient in AP, rotated towards the patient's left for LAO and towards the head
  // for cranial; the source (the centre of projection) is on the opposite side.
  const Vec3 detector = std::cos(cra) * (std::cos(lao) * a + std::sin(lao) * left) + std::sin(cra) * s;
  CameraPose p = make_pose(-detector, kCarmDistanceScale);
  p.mirror_x = true;
  return p;
}

}  // namespace vascsim::render
