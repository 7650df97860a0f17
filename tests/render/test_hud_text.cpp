// The HUD's line on what the hand gets (render/hud.hpp hand_line): the force sent to the device beside the
// model's, how far the model's tool is behind the hand and how old the force is. Pure text, no GL context.

#include <gtest/gtest.h>

#include <limits>

#include "vascsim/render/hud.hpp"

namespace vascsim::render {
namespace {

HudStats driven() {
  HudStats s;
  s.device = "scripted";
  s.tool_force_n = 5.1e-3;
  s.device_force_n = 13.8e-3;
  s.tool_lag_m = 0.6e-3;
  s.force_age_ms = 155.0;
  return s;
}

TEST(HudText, TheHandLineShowsTheSentForceBesideTheModelsTheLagAndTheAge) {
  const std::string line = hand_line(driven());
  EXPECT_EQ(line, "hand: 0.0138 N sent (tool 0.0051 N), tool 0.60 mm behind, force 155 ms old");
}

TEST(HudText, NoHandLineWithoutADeviceOrAKnownSentForce) {
  HudStats s = driven();
  s.device.clear();
  EXPECT_EQ(hand_line(s), "");
  s = driven();
  s.device_force_n = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(hand_line(s), "");
  s = driven();
  s.tool_lag_m = std::numeric_limits<double>::quiet_NaN();  // a model that does not say: the rest still shown
  s.force_age_ms = 0.0;
  EXPECT_EQ(hand_line(s), "hand: 0.0138 N sent (tool 0.0051 N)");
}

}  // namespace
}  // namespace vascsim::render
