// Whether a tool will touch the body, from the geometry: the closest approach of its swept path (load factor)
// or of its trajectory (device) to the nodes, checked against a hand-computed distance.

#include <gtest/gtest.h>

#include "vascsim/run/tool_reach.hpp"

namespace vascsim {
namespace {

// A row of nodes along x at y = z = 0.
Vec3Array row_of_nodes() {
  Vec3Array x;
  for (int i = -10; i <= 10; ++i) x.emplace_back(1e-4 * i, 0.0, 0.0);
  return x;
}

TEST(ToolReach, LoadPathFindsTheClosestApproachAndWhetherItTouches) {
  RigidObstacle sphere;
  sphere.name = "ball";
  sphere.radius_m = 1e-3;
  sphere.a_m = sphere.b_m = sphere.tool_point_m = Vec3(0, 3e-3, 0);  // 2 mm gap at s = 0
  sphere.motion_m = Vec3(0, -1.5e-3, 0);                             // 0.5 mm gap at s = 1
  ToolReach r = tool_reach_by_load(sphere, row_of_nodes());
  EXPECT_FALSE(r.touches());
  EXPECT_NEAR(r.clearance_m, 0.5e-3, 1e-12);  // at the end of the path: exact (a sample lies there)
  EXPECT_DOUBLE_EQ(r.at, 1.0);
  sphere.motion_m = Vec3(0, -2.5e-3, 0);  // now it passes 0.5 mm into the row
  r = tool_reach_by_load(sphere, row_of_nodes());
  EXPECT_TRUE(r.touches());
  EXPECT_NEAR(r.clearance_m, -0.5e-3, 1e-12);
  // A path that passes the nodes sideways and away again: the closest point lies inside the path, and the
  // samples (a quarter radius apart) find it to within 1/32 of a radius (the chord's sag).
  sphere.a_m = sphere.b_m = sphere.tool_point_m = Vec3(-5e-3, 1.2e-3, 0);
  sphere.motion_m = Vec3(10e-3, 0, 0);
  r = tool_reach_by_load(sphere, row_of_nodes());
  EXPECT_NEAR(r.clearance_m, 0.2e-3, 1e-3 / 32);
  EXPECT_FALSE(r.touches());
  const std::string w = tool_reach_warning(r, sphere, 2);
  EXPECT_NE(w.find("tool 'ball' will never touch the tissue"), std::string::npos) << w;
  EXPECT_NE(w.find("obstacles.2: centre_m and motion_m"), std::string::npos) << w;
}

TEST(ToolReach, TrajectoryOfADevicePosedCatheter) {
  const RigidObstacle catheter = make_catheter("catheter", Vec3(0, 2e-3, 0), Vec3(0, -1, 0), 2e-3, 10e-3);
  const Eigen::Quaterniond down = orientation_pointing(Vec3(0, -1, 0));
  // The tip goes down from 2 mm above the row to 0.3 mm above it, and back up.
  DevicePose p0, p1, p2;
  p0.time_s = 0.0, p0.position_m = Vec3(0, 2e-3, 0), p0.orientation = down;
  p1.time_s = 1.0, p1.position_m = Vec3(0, 0.3e-3, 0), p1.orientation = down;
  p2.time_s = 2.0, p2.position_m = Vec3(0, 2e-3, 0), p2.orientation = down;
  const Trajectory t({p0, p1, p2});
  ToolReach r = tool_reach_on_trajectory(catheter, t, 2.0, row_of_nodes());
  EXPECT_TRUE(r.by_time);
  EXPECT_FALSE(r.touches());
  EXPECT_NEAR(r.clearance_m, 0.3e-3, 1e-12);  // at the sample t = 1 s, where the tip is lowest
  EXPECT_NEAR(r.at, 1.0, 1e-12);
  // Only the first half second: the tip is still 1.15 mm above.
  r = tool_reach_on_trajectory(catheter, t, 0.5, row_of_nodes());
  EXPECT_NEAR(r.clearance_m, 1.15e-3, 1e-12);
  // Pressed 0.3 mm past the row: touches.
  p1.position_m = Vec3(0, -0.3e-3, 0);
  r = tool_reach_on_trajectory(catheter, Trajectory({p0, p1, p2}), 2.0, row_of_nodes());
  EXPECT_TRUE(r.touches());
  EXPECT_NEAR(r.clearance_m, -0.3e-3, 1e-12);  // the deepest pass, at t = 1 s
  // Asked for the first contact only (a session needs no more): the first pose past the row, on the way down
  // (the tip crosses the row 2/2.3 of the way to t = 1 s), not the deepest.
  const ToolReach first =
      tool_reach_on_trajectory(catheter, Trajectory({p0, p1, p2}), 2.0, row_of_nodes(), true);
  EXPECT_TRUE(first.touches());
  EXPECT_GT(first.clearance_m, -0.3e-3 + 1e-6);
  EXPECT_GT(first.at, 2.0 / 2.3 - 1e-9);
  EXPECT_LT(first.at, 1.0);
}

}  // namespace
}  // namespace vascsim
