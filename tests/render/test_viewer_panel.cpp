// The panel's requests become live-session commands (viewer/session_panel): record from rest and stop (a
// recording file), replay it (a scripted device drives the tool), another model, edited settings (a rebuild
// with the edited value), a bad value (a message, the running simulation kept). Lockstep, no GL context: the
// panel's wiring without a window (the buttons themselves are Dear ImGui's).

#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <filesystem>

#include "vascsim/viewer/frame_builder.hpp"
#include "vascsim/viewer/session_panel.hpp"

namespace vascsim::viewer {
namespace {

namespace fs = std::filesystem;

const std::string kPanelBlock = std::string(VASCSIM_SOURCE_DIR) + "/tests/data/haptic-block.json";

struct ViewerPanel : ::testing::Test {
  FrameExchange<ViewerFrame> exchange;
  OverlayRequests overlays;
  MouseKeyboardDevice mouse;
  FrameBuilder builder{exchange, mouse, overlays, false};
  std::unique_ptr<LiveSession> session;
  render::HudControls controls;
  std::unique_ptr<SessionPanel> panel;

  void SetUp() override {
    const Scene scene = load_scene(kPanelBlock);
    LiveOptions options;
    options.lockstep = true;
    session = std::make_unique<LiveSession>(scene, mouse, builder, options);
    panel =
        std::make_unique<SessionPanel>(*session, scene, kPanelBlock, std::vector<std::string>{}, controls);
  }
  // One frame after the panel's requests: what the render thread would draw.
  const ViewerFrame& frame_after(const render::HudRequests& r) {
    panel->handle(r, {});
    session->step_lockstep();
    exchange.update();
    return exchange.front();
  }
};

TEST_F(ViewerPanel, RecordStopAndReplayThroughThePanel) {
  const fs::path file = fs::temp_directory_path() / ("vascsim-panel-" + std::to_string(::getpid()) + ".csv");
  controls.record_path = file.string();
  render::HudRequests record;
  record.toggle_recording = true;
  EXPECT_TRUE(frame_after(record).info.recording);
  EXPECT_EQ(exchange.front().info.build, 2u);  // recording starts from rest: a rebuild
  for (int k = 0; k < 30; ++k) frame_after({});
  const ViewerFrame& stopped = frame_after(record);  // the same button stops it
  EXPECT_FALSE(stopped.info.recording);
  EXPECT_NE(stopped.info.message.find("31 ticks"), std::string::npos) << stopped.info.message;
  ASSERT_TRUE(fs::exists(file));

  controls.replay_path = file.string();
  render::HudRequests replay;
  replay.start_replay = true;
  const ViewerFrame& replaying = frame_after(replay);
  EXPECT_EQ(replaying.info.device, "scripted");
  EXPECT_EQ(replaying.info.build, 3u);
  fs::remove(file);
}

TEST_F(ViewerPanel, ModelAndSettingsRebuildAndABadValueIsAMessage) {
  // The block scene's model is xpbd; its damping is among the settings the panel offers.
  EXPECT_EQ(controls.model, "xpbd");
  auto damping = std::find_if(controls.model_settings.begin(), controls.model_settings.end(),
                              [](const JsonField& f) { return f.key == "xpbd.damping_per_s"; });
  ASSERT_NE(damping, controls.model_settings.end());
  EXPECT_EQ(damping->value, 60.0);  // the file's value
  damping->value = 120.0;
  controls.youngs_modulus_pa = 4e5;
  render::HudRequests apply;
  apply.apply_settings = true;
  const ViewerFrame& rebuilt = frame_after(apply);
  EXPECT_EQ(rebuilt.info.build, 2u);
  EXPECT_TRUE(panel->message().empty()) << panel->message();
  damping = std::find_if(controls.model_settings.begin(), controls.model_settings.end(),
                         [](const JsonField& f) { return f.key == "xpbd.damping_per_s"; });
  ASSERT_NE(damping, controls.model_settings.end());
  EXPECT_EQ(damping->value, 120.0);  // read back from the rebuilt scene
  EXPECT_EQ(controls.youngs_modulus_pa, 4e5);

  controls.model = "quasi_static";  // any device-driven model, from the registry
  render::HudRequests change;
  change.change_model = true;
  EXPECT_EQ(frame_after(change).model, "quasi_static");
  EXPECT_TRUE(std::all_of(controls.model_settings.begin(), controls.model_settings.end(),
                          [](const JsonField& f) { return f.key.rfind("quasi_static.", 0) == 0; }));

  controls.overrides = "material.poisson_ratio=0.7";  // out of range: one message, nothing rebuilt
  const std::uint64_t build = exchange.front().info.build;
  EXPECT_EQ(frame_after(apply).info.build, build);
  EXPECT_NE(panel->message().find("poisson_ratio"), std::string::npos) << panel->message();
}

}  // namespace
}  // namespace vascsim::viewer
