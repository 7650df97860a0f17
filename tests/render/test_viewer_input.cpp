// The mouse drives the catheter in the viewer's own frames: the live session in lockstep with the viewer's
// frame builder (which fits the mouse device to the scene, mouse_workspace.hpp) on tests/data/haptic-block.json
// (a 6 x 6 x 3 mm block, the catheter's tip 0.2 mm above its top). A scripted input sequence advances the
// catheter with the wheel; the frames the render thread would draw show no force while the tip is above the
// block and a force once it presses in, with the arrow pointing into the tissue. No GL context is needed.

#include <gtest/gtest.h>

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
  EXPECT_LT(tip_z, 0.0026);     // the proxy followed the wheel into the block (0.7 mm, within 0.3 mm)
  EXPECT_GT(f.tool_force_n, 1e-3);  // as the scripted press of the haptic session at this depth (> 1 mN)
  ASSERT_TRUE(f.render.force.has_value());
  EXPECT_LT(f.render.force->force_n.z(), -0.9 * f.render.force->force_n.norm());  // the arrow points down, into it
  ASSERT_EQ(f.render.tools.size(), 1u);
  EXPECT_NEAR(f.render.tools[0].tip_m.z(), static_cast<float>(tip_z), 1e-7f);  // drawn where it is
}

}  // namespace
}  // namespace vascsim::viewer
