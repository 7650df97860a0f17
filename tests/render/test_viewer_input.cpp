// The mouse drives the catheter in the viewer's own frames: the live session in lockstep with the viewer's
// frame builder (which fits the mouse device to the scene, mouse_workspace.hpp) on
// tests/data/haptic-block.json (a 6 x 6 x 3 mm block, the catheter's tip 0.2 mm above its top). A scripted
// input sequence advances the catheter with the wheel; the frames the render thread would draw show no force
// while the tip is above the block and a force once it presses in, with the arrow pointing into the tissue.
// No GL context is needed.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "vascsim/scene/scene.hpp"
#include "vascsim/viewer/frame_builder.hpp"
#include "vascsim/viewer/mouse_workspace.hpp"

namespace vascsim::viewer {
namespace {

const std::string kBlock = std::string(VASCSIM_SOURCE_DIR) + "/tests/data/haptic-block.json";

TEST(ViewerInput, MouseWheelAdvancesTheCatheterUntilTheFramesShowAForce) {
  FrameExchange<ViewerFrame> exchange;
  OverlayRequests overlays;
  MouseKeyboardDevice mouse;
  FrameBuilder builder(exchange, mouse, overlays, false);
  LiveOptions options;
  options.lockstep = true;
  LiveSession session(load_scene(kBlock), mouse, builder, options);
  ASSERT_TRUE(exchange.update());
  const double step =
      mouse_settings(load_scene(kBlock), 0, Vec3::Zero(), Vec3(0.006, 0.006, 0.003)).scroll_step_m;
  EXPECT_NEAR(step, 1e-4, 1e-12);  // the block's smallest side (3 mm) / 30: 0.1 mm per notch
  // 20 idle frames, then one notch per frame for 9 frames (0.9 mm: 0.7 mm into the block), then 60 holding.
  double force_above = 0.0, tip_z = 1.0;
  for (int k = 0; k < 89; ++k) {
    if (k >= 20 && k < 29) mouse.scroll(1.0);
    session.step_lockstep();
    ASSERT_TRUE(exchange.update());
    const ViewerFrame& f = exchange.front();
    tip_z = f.info.sample.tool_position_m.z();
    if (tip_z > 0.003) force_above = std::max(force_above, f.tool_force_n);
  }
  const ViewerFrame& f = exchange.front();
  std::printf("[ viewer   ] tool point z = %.3f mm, tool force %.4g N\n", 1e3 * tip_z, f.tool_force_n);
  EXPECT_EQ(force_above, 0.0);  // exactly: no node in contact, no load
  // The proxy followed the wheel into the block: 0.7 mm deep is z = 2.3 mm (measured 2.34); within 0.3 mm for
  // the tissue pushing back.
  EXPECT_LT(tip_z, 0.0026);
  EXPECT_GT(f.tool_force_n,
            1e-3);  // as the scripted press of the haptic session at this depth (> 1 mN; 19 mN)
  ASSERT_TRUE(f.render.force.has_value());
  // The arrow (the tool's force on the tissue) points down, into the block: 90 % of it along -z, as in
  // LiveSession.LockstepMouseAdvancesTheCatheterUntilItPressesTheBlock (the tip off the lattice tilts it).
  EXPECT_LT(f.render.force->force_n.z(), -0.9 * f.render.force->force_n.norm());
  ASSERT_EQ(f.render.tools.size(), 1u);
  EXPECT_NEAR(f.render.tools[0].tip_m.z(), static_cast<float>(tip_z), 1e-7f);  // drawn where it is
  // The colour fields are where the press is: the largest displacement, and (after one more frame with the
  // stress field asked for) the largest von Mises stress, lie within 2 mm of the tool point (the block is 6 x
  // 6 mm; the tip's radius is 1 mm and the node spacing 0.5 mm). At rest the stress is zero up to rounding.
  const auto peak_distance = [&](const render::RenderFrame& r) {
    const auto top =
        std::max_element(r.scalar->values.begin(), r.scalar->values.end()) - r.scalar->values.begin();
    return (r.positions_m[static_cast<std::size_t>(top)].cast<double>() - f.info.sample.tool_position_m)
        .norm();
  };
  ASSERT_TRUE(f.render.scalar.has_value());
  EXPECT_EQ(f.render.scalar->label, "displacement");
  EXPECT_LT(peak_distance(f.render), 2e-3);
  overlays.stress = true;
  session.step_lockstep();
  ASSERT_TRUE(exchange.update());
  const render::RenderFrame& r = exchange.front().render;
  EXPECT_EQ(r.scalar->label, "von Mises stress");
  EXPECT_EQ(r.scalar->unit, "kPa");
  std::printf("[ viewer   ] largest von Mises stress on the surface %.3g kPa, %.2f mm from the tool point\n",
              r.scalar->max, 1e3 * peak_distance(r));
  EXPECT_LT(peak_distance(r), 2e-3);

  MouseKeyboardDevice idle;
  FrameBuilder rest_builder(exchange, idle, overlays, false);
  LiveSession rest(load_scene(kBlock), idle, rest_builder, options);  // publishes the rest state
  ASSERT_TRUE(exchange.update());
  EXPECT_LT(exchange.front().render.scalar->max, 1e-6f);  // kPa: F = I to rounding at rest
}

}  // namespace
}  // namespace vascsim::viewer
