// Camera math without GL: view/projection conventions, orbit/pan/zoom/reset, the C-arm view, and the
// input mapping of the camera controller.

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "vascsim/render/camera.hpp"
#include "vascsim/render/camera_controller.hpp"

namespace vascsim::render {
namespace {

Eigen::Vector3d project(const CameraPose& p, const Vec3& x, double aspect = 1.0) {
  const Eigen::Vector4d clip = p.projection(aspect) * p.view() * x.homogeneous();
  return clip.head<3>() / clip.w();
}

Bounds unit_bounds() {
  Bounds b;
  b.min = Vec3(-1, -1, -1);
  b.max = Vec3(1, 1, 1);
  return b;
}

TEST(RenderCamera, ViewMatrixMapsTheTargetOntoTheAxisAndTheEyeToTheOrigin) {
  CameraPose p;
  p.eye_m = Vec3(1, 2, 3);
  p.target_m = Vec3(-1, 0.5, 2);
  p.up = Vec3::UnitZ();
  const Eigen::Matrix4d v = p.view();
  EXPECT_LT((v * p.eye_m.homogeneous()).head<3>().norm(), 1e-12);
  const Vec3 t = (v * p.target_m.homogeneous()).head<3>();
  EXPECT_NEAR(t.x(), 0.0, 1e-12);
  EXPECT_NEAR(t.y(), 0.0, 1e-12);
  EXPECT_NEAR(t.z(), -(p.target_m - p.eye_m).norm(), 1e-12);  // in front: negative z
  // The rotation part is orthonormal.
  EXPECT_LT((v.block<3, 3>(0, 0) * v.block<3, 3>(0, 0).transpose() - Mat3::Identity()).norm(), 1e-12);
}

TEST(RenderCamera, ProjectionMapsNearAndFarToTheDepthRange) {
  CameraPose p;
  p.eye_m = Vec3::Zero();
  p.target_m = -Vec3::UnitZ();
  p.up = Vec3::UnitY();
  p.near_m = 0.1;
  p.far_m = 5.0;
  EXPECT_NEAR(project(p, Vec3(0, 0, -0.1)).z(), -1.0, 1e-9);
  EXPECT_NEAR(project(p, Vec3(0, 0, -5.0)).z(), 1.0, 1e-9);
  // The top of the field of view at depth 1 is y = tan(fov / 2).
  const double top = std::tan(0.5 * p.fov_y_deg * M_PI / 180.0);
  EXPECT_NEAR(project(p, Vec3(0, top, -1.0)).y(), 1.0, 1e-9);
  EXPECT_NEAR(project(p, Vec3(2.0 * top, 0, -1.0), 2.0).x(), 1.0, 1e-9);
}

TEST(RenderCamera, FitFramesTheBoundingSphereAndResetRestoresTheHomeView) {
  OrbitCamera cam;
  cam.fit(unit_bounds());
  const CameraPose home = cam.pose();
  // Every corner of the box is inside the picture, and the sphere nearly fills it.
  for (int i = 0; i < 8; ++i) {
    const Vec3 corner((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1);
    const Vec3 ndc = project(home, corner);
    EXPECT_LT(ndc.cwiseAbs().maxCoeff(), 1.0) << corner.transpose();
  }
  EXPECT_NEAR(cam.distance_m(), 1.05 * std::sqrt(3.0) / std::sin(17.5 * M_PI / 180.0), 1e-9);
  // Home: from anterior (+y), above (pitch 15), superior (+z) up on screen.
  EXPECT_GT(home.eye_m.y(), 0.0);
  EXPECT_GT(home.eye_m.z(), 0.0);
  EXPECT_GT(project(home, Vec3(0, 0, 0.5)).y(), 0.0);

  cam.orbit(100, -40);
  cam.pan(30, 10, 600);
  cam.zoom(3);
  EXPECT_GT((cam.pose().eye_m - home.eye_m).norm(), 0.1);
  cam.reset();
  EXPECT_LT((cam.pose().eye_m - home.eye_m).norm(), 1e-12);
  EXPECT_LT((cam.pose().target_m - home.target_m).norm(), 1e-12);
}

TEST(RenderCamera, OrbitKeepsTheDistanceAndClampsThePitch) {
  OrbitCamera cam;
  cam.fit(unit_bounds());
  const double d = cam.distance_m();
  cam.orbit(300, 0);  // 90 degrees
  EXPECT_NEAR(cam.yaw_deg(), -90.0, 1e-9);
  EXPECT_NEAR((cam.pose().eye_m - cam.target_m()).norm(), d, 1e-9);
  cam.orbit(0, 10000);
  EXPECT_DOUBLE_EQ(cam.pitch_deg(), 85.0);
  cam.orbit(0, -20000);
  EXPECT_DOUBLE_EQ(cam.pitch_deg(), -85.0);
}

TEST(RenderCamera, PanMovesTheSceneWithTheCursor) {
  OrbitCamera cam;
  cam.fit(unit_bounds());
  const int h = 800;
  const Vec3 point = cam.target_m();
  const double x0 = project(cam.pose(), point, 1.0).x();
  cam.pan(80, 0, h);  // 80 px to the right = 0.2 of the half-height in NDC (aspect 1)
  const double x1 = project(cam.pose(), point, 1.0).x();
  EXPECT_NEAR(x1 - x0, 2.0 * 80 / h, 1e-6);
}

TEST(RenderCamera, ZoomScalesTheDistanceWithinLimits) {
  OrbitCamera cam;
  cam.fit(unit_bounds());
  const double d = cam.distance_m();
  cam.zoom(1);
  EXPECT_NEAR(cam.distance_m(), 0.9 * d, 1e-12);
  cam.zoom(-2);
  EXPECT_NEAR(cam.distance_m(), d / 0.9, 1e-12);
  cam.zoom(1000);
  EXPECT_NEAR(cam.distance_m(), 0.02 * d, 1e-12);
  cam.zoom(-10000);
  EXPECT_NEAR(cam.distance_m(), 20.0 * d, 1e-12);
}

TEST(RenderCamera, CArmApShowsThePatientsRightOnTheLeftAndLaoTurnsAboutTheSuperiorAxis) {
  OrbitCamera cam;  // superior +z, anterior +y: the patient's right is +x
  cam.fit(unit_bounds());
  const CameraPose ap = cam.carm_pose(0, 0);
  EXPECT_TRUE(ap.mirror_x);
  // The source is posterior, the detector (viewer) anterior.
  EXPECT_LT(ap.eye_m.y(), -1.0);
  EXPECT_NEAR(ap.eye_m.x(), 0.0, 1e-12);
  EXPECT_LT(project(ap, Vec3(0.5, 0, 0)).x(), 0.0);  // patient's right on the left of the screen
  EXPECT_GT(project(ap, Vec3(0, 0, 0.5)).y(), 0.0);  // head up
  // LAO 90: the detector on the patient's left (-x), the source on the right.
  const CameraPose lao = cam.carm_pose(90, 0);
  EXPECT_GT(lao.eye_m.x(), 1.0);
  EXPECT_NEAR(lao.eye_m.z(), 0.0, 1e-9);
  // The source is kCarmDistanceScale orbit distances away; its narrower field of view frames the target's
  // plane as the orbit view does (same half-height at the target).
  EXPECT_NEAR((lao.eye_m - lao.target_m).norm(), OrbitCamera::kCarmDistanceScale * cam.distance_m(), 1e-9);
  EXPECT_NEAR((lao.eye_m - lao.target_m).norm() * std::tan(0.5 * lao.fov_y_deg * M_PI / 180.0),
              cam.distance_m() * std::tan(0.5 * cam.fov_y_deg() * M_PI / 180.0), 1e-12);
  // Cranial 30: the detector towards the head, the source towards the feet.
  const CameraPose cra = cam.carm_pose(0, 30);
  EXPECT_LT(cra.eye_m.z(), 0.0);
  EXPECT_NEAR(std::atan2(-cra.eye_m.z(), -cra.eye_m.y()) * 180.0 / M_PI, 30.0, 1e-9);
  // The device frame of the mirrored view is right-handed and points into the picture from the detector.
  const ViewFrame v = ap.view_frame();
  EXPECT_LT((v.right_m.cross(v.up_m) + v.forward_m).norm(), 1e-12);
  EXPECT_LT(v.forward_m.y(), 0.0);  // from the anterior detector into the patient
  EXPECT_LT(v.right_m.x(), 0.0);    // screen right = patient's left
}

TEST(RenderCamera, ViewFrameOfTheLitViewIsTheCameraAxes) {
  OrbitCamera cam;
  cam.fit(unit_bounds());
  const CameraPose p = cam.pose();
  const ViewFrame v = p.view_frame();
  EXPECT_LT((v.forward_m - p.forward()).norm(), 1e-12);
  EXPECT_LT((v.right_m.cross(v.up_m) + v.forward_m).norm(), 1e-12);
  EXPECT_GT(project(p, p.target_m + 0.3 * v.right_m).x(), 0.0);
  EXPECT_GT(project(p, p.target_m + 0.3 * v.up_m).y(), 0.0);
}

TEST(RenderCamera, ControllerOrbitsPansZoomsAndLeavesCtrlDragToTheTool) {
  OrbitCamera cam;
  cam.fit(unit_bounds());
  CameraController c(cam);
  EXPECT_TRUE(c.button(MouseButton::left, true, false, false));
  c.cursor(100, 100, 600);
  EXPECT_TRUE(c.cursor(110, 100, 600));
  EXPECT_NEAR(cam.yaw_deg(), -3.0, 1e-9);
  EXPECT_TRUE(c.button(MouseButton::left, false, false, false));
  EXPECT_FALSE(c.cursor(200, 100, 600));  // no drag: nothing moves
  const Vec3 target = cam.target_m();
  EXPECT_TRUE(c.button(MouseButton::right, true, false, false));
  c.cursor(0, 0, 600);
  c.cursor(50, 0, 600);
  EXPECT_GT((cam.target_m() - target).norm(), 0.0);
  c.button(MouseButton::right, false, false, false);
  EXPECT_FALSE(c.button(MouseButton::left, true, false, true));  // ctrl + left: the tool's
  const double d = cam.distance_m();
  c.scroll(2);
  EXPECT_LT(cam.distance_m(), d);
  EXPECT_TRUE(c.key('R'));
  EXPECT_DOUBLE_EQ(cam.yaw_deg(), 0.0);
  EXPECT_FALSE(c.key('Q'));
}

}  // namespace
}  // namespace vascsim::render
