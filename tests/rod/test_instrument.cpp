// A flexible instrument as a scene gives it (rod/instrument.hpp): the presets' values, the block's keys and
// its errors, the hand's drive between knots, and the rod it builds.

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

#include "vascsim/core/error.hpp"
#include "vascsim/rod/instrument.hpp"

namespace vascsim::rod {
namespace {

using nlohmann::json;

InstrumentSpec read(const json& block) {
  JsonReader r(block, "instrument", "scene.json");
  return read_instrument(r);
}

std::string error_of(const json& block) {
  try {
    read(block);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// The presets carry the values docs/model/26-rod.md section 26.7 cites: exact numbers, so a changed value
// fails (tolerance: the doubles' round-off).
TEST(Instrument, ThePresetsCarryTheirSourcedValues) {
  const InstrumentSpec w = instrument_preset("guidewire-035");
  EXPECT_DOUBLE_EQ(w.section.outer_diameter_m, 0.889e-3);
  EXPECT_DOUBLE_EQ(w.section.youngs_modulus_pa, 60.3e9);
  EXPECT_DOUBLE_EQ(w.section.inner_diameter_m, 0.0);
  EXPECT_EQ(w.tip, TipShape::J);
  const InstrumentSpec f = instrument_preset("guidewire-014");
  EXPECT_DOUBLE_EQ(f.section.outer_diameter_m, 0.3556e-3);
  EXPECT_DOUBLE_EQ(f.section.youngs_modulus_pa, 48e9);
  const InstrumentSpec c = instrument_preset("catheter-5fr-angled");
  EXPECT_DOUBLE_EQ(c.section.outer_diameter_m, 5e-3 / 3.0);
  EXPECT_DOUBLE_EQ(c.section.inner_diameter_m, 0.9652e-3);
  EXPECT_DOUBLE_EQ(c.section.youngs_modulus_pa, 0.5e9);
  EXPECT_EQ(c.tip, TipShape::Angled);
  EXPECT_THROW(instrument_preset("guidewire-038"), InputError);
  // The rod a preset builds bends with E pi D^4 / 64 (relative 1e-12: one product of doubles).
  const CosseratRod rod = make_instrument_rod(w, Vec3::Zero(), Vec3::UnitZ(), Vec3::UnitX());
  const double ei = 60.3e9 * std::numbers::pi * std::pow(0.889e-3, 4) / 64.0;
  EXPECT_NEAR(rod.stiffness().bend_twist_n_m2[0], ei, 1e-12 * ei);
  EXPECT_EQ(rod.num_edges(), 200);  // 0.2 m in 1 mm edges
}

TEST(Instrument, SceneKeysOverrideThePreset) {
  const InstrumentSpec s = read(json::parse(R"({"preset": "guidewire-035", "youngs_modulus_pa": 30e9,
      "length_m": 0.1, "tip": {"shape": "angled", "angle_deg": 30}, "friction": 0.02,
      "drive": [[0, 0.01, 0], [1, 0.05, 90]]})"));
  EXPECT_DOUBLE_EQ(s.section.youngs_modulus_pa, 30e9);
  // G keeps the preset's ratio to E (its Poisson ratio): E / 2.6.
  EXPECT_NEAR(s.section.shear_modulus_pa, 30e9 / 2.6, 1e-6);
  EXPECT_EQ(s.tip, TipShape::Angled);
  EXPECT_DOUBLE_EQ(s.tip_angle_deg, 30.0);
  EXPECT_DOUBLE_EQ(s.tip_radius_m, 3e-3);  // the preset's radius
  EXPECT_DOUBLE_EQ(s.friction, 0.02);
  ASSERT_EQ(s.drive.size(), 2u);
  // Without a preset every value is the scene's: G from its Poisson ratio.
  const InstrumentSpec o = read(json::parse(R"({"outer_diameter_m": 1e-3, "youngs_modulus_pa": 1e9,
      "poisson_ratio": 0.25, "density_kg_m3": 1000, "length_m": 0.05, "drive": [[0, 0.01, 0]]})"));
  EXPECT_DOUBLE_EQ(o.section.shear_modulus_pa, 1e9 / 2.5);
  EXPECT_EQ(o.tip, TipShape::Straight);
}

// Each mistake is named with its key, in one line.
TEST(Instrument, MistakesNameTheirKey) {
  EXPECT_NE(error_of(json::parse(R"({"youngs_modulus_pa": 1e9, "poisson_ratio": 0.3, "density_kg_m3": 1000,
      "length_m": 0.05, "drive": [[0, 0.01, 0]]})"))
                .find("'instrument.outer_diameter_m': missing"),
            std::string::npos);
  EXPECT_NE(error_of(json::parse(R"({"preset": "guidewire-035", "frictoin": 0.1, "drive": [[0, 0.01, 0]]})"))
                .find("frictoin"),
            std::string::npos);
  EXPECT_NE(error_of(json::parse(R"({"preset": "guidewire-035", "drive": [[1, 0.01, 0], [0.5, 0.02, 0]]})"))
                .find("times start at 0 or later and increase"),
            std::string::npos);
  EXPECT_NE(error_of(json::parse(R"({"preset": "guidewire-035", "drive": [[0, 0.3, 0]]})")).find("length_m"),
            std::string::npos);
  EXPECT_NE(
      error_of(json::parse(R"({"preset": "guidewire-035", "drive": [[0, 0.01]]})")).find("three numbers"),
      std::string::npos);
  EXPECT_NE(error_of(json::parse(R"({"preset": "guidewire-035"})")).find("'instrument.drive': missing"),
            std::string::npos);
  EXPECT_NE(error_of(json::parse(R"({"preset": "wire"})")).find("guidewire-035"), std::string::npos);
}

TEST(Instrument, TheDriveIsLinearBetweenKnotsAndHeldOutside) {
  const std::vector<DriveKnot> d{{0.5, 0.01, 0.0}, {1.5, 0.03, 90.0}};
  const double deg = std::numbers::pi / 180.0;
  EXPECT_DOUBLE_EQ(drive_at(d, 0.0).first, 0.01);
  EXPECT_NEAR(drive_at(d, 1.0).first, 0.02, 1e-15);
  EXPECT_NEAR(drive_at(d, 1.0).second, 45.0 * deg, 1e-15);
  EXPECT_DOUBLE_EQ(drive_at(d, 2.0).first, 0.03);
  EXPECT_NEAR(drive_at(d, 2.0).second, 90.0 * deg, 1e-15);
}

// The J tip turns back on the shaft: the last edge is the chord of the arc's last 1 mm, which runs against
// the shaft turned back by half that edge's angle, 1 mm / 3 mm / 2 (to the round-off of the arc's nodes,
// 1e-9).
TEST(Instrument, TheJTipTurnsBackOnTheShaft) {
  InstrumentSpec s = instrument_preset("guidewire-035");
  s.length_m = 0.05;
  const CosseratRod rod = make_instrument_rod(s, Vec3::Zero(), Vec3::UnitZ(), Vec3::UnitX());
  const Vec3Array& x = rod.rest_shape().nodes;
  const Vec3 last = (x.back() - x[x.size() - 2]).normalized();
  EXPECT_NEAR(last.dot(Vec3::UnitZ()), -std::cos(0.5 * 1e-3 / 3e-3), 1e-9);
  // Towards the given normal: the hook lies on +x.
  EXPECT_GT(x.back().x(), 5e-3);
}

}  // namespace
}  // namespace vascsim::rod
