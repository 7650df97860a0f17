// A flexible instrument advanced through a vessel's lumen by a scene (run/navigation.hpp, `vascsim
// navigate`): it stays in the lumen, the hand's load balances the wall's, turning the proximal end turns the
// tip, and a scene that cannot be navigated says why.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "support/cli_capture.hpp"
#include "support/run_helpers.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/run/navigation.hpp"

namespace vascsim {
namespace {

using nlohmann::json;

const std::string kAorta = "scenes/navigation/aorta-bent-guidewire.json";

// The bundled scene's wire fed into the arch (10 to 50 mm at 20 mm/s), frictionless: the rod is then in
// equilibrium under the hand's load and the wall's contact forces alone, so the hand's force along the port's
// axis is minus the contact forces' sum along it. The two come from different parts (the rod's elastic forces
// on the held nodes; the contact's multipliers); tolerance 1e-4 of the force (the equilibria are solved to
// 1e-6 of the load scale).
TEST(Navigation, TheWireStaysInTheLumenAndTheHandBalancesTheWall) {
  const Scene scene = load_scene(test::source_path(kAorta),
                                 {"instrument.friction=0", "instrument.drive=[[0,0.01,0],[2,0.05,0]]"});
  const NavigationResult r = run_navigation(scene, {});
  ASSERT_EQ(r.frames.size(), 201u);
  const Vec3 axis = build_centerline(scene.geometry.centerline).tangent(0.0);
  const double radius = 0.5 * scene.instrument->section.outer_diameter_m;
  int in_contact = 0;
  for (const NavigationFrame& f : r.frames) {
    SCOPED_TRACE(::testing::Message() << "t = " << f.time_s << " s, " << f.inserted_m * 1e3 << " mm in");
    EXPECT_TRUE(f.converged);
    // The issue's bound: no point of the rod farther outside the lumen than a tenth of its radius.
    EXPECT_LT(f.outside_max_m, 0.1 * radius);
    const double wall_along = -f.wall_force_sum_n.dot(axis);
    EXPECT_NEAR(f.insertion_force_n, wall_along, 1e-4 * std::max(std::abs(wall_along), 1e-3));
    in_contact += f.nodes_in_contact > 0 ? 1 : 0;
  }
  // The tip meets the arch's outer wall before 50 mm: some frames carry a wall force, and pushing needs one.
  EXPECT_GT(in_contact, 10);
  EXPECT_GT(r.frames.back().insertion_force_n, 0.0);
  EXPECT_NEAR(r.frames.back().inserted_m, 0.05, 1e-12);
}

// In a straight vessel nothing resists a frictionless turn: the angled tip's offset from the axis turns with
// the proximal end (90 degrees, to 1e-3 rad: the equilibria's tolerance), and the hand feels no torque.
TEST(Navigation, TurningTheProximalEndTurnsTheTip) {
  const json doc = json::parse(R"({
    "name": "straight",
    "model": "quasi_static",
    "geometry": { "type": "vessel", "centerline": { "type": "straight", "length_m": 0.03 },
                  "outer_radius_m": 2e-3, "wall_thickness_m": 0.3e-3, "node_spacing_m": 0.5e-3 },
    "regions": [ { "name": "end", "select": { "type": "cylinder_end", "end": "start" }, "bc": { "type": "fixed" } } ],
    "instrument": { "preset": "guidewire-014", "length_m": 0.04, "friction": 0,
                    "drive": [[0, 0.02, 0], [0.1, 0.02, 0], [0.5, 0.02, 90]] }
  })");
  const Scene scene = parse_scene(doc, "straight.json");
  const NavigationResult r = run_navigation(scene, {});
  auto offset = [](const Vec3& tip) { return Vec3(tip.x(), tip.y(), 0.0); };  // the centre-line is the z axis
  const Vec3 a = offset(r.frames[10].tip_m), b = offset(r.frames.back().tip_m);
  ASSERT_GT(a.norm(), 1e-4);
  const double turned = std::atan2(a.cross(b).z(), a.dot(b));
  EXPECT_NEAR(turned, 0.5 * std::numbers::pi, 1e-3);
  for (const NavigationFrame& f : r.frames) EXPECT_NEAR(f.torque_n_m, 0.0, 1e-9);
}

TEST(Navigation, AScenesThatCannotBeNavigatedSayWhy) {
  const std::string path = test::source_path(kAorta);
  auto error_of = [&](const std::vector<std::string>& sets) {
    try {
      run_navigation(load_scene(path, sets), {});
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error_of({"instrument.outer_diameter_m=0.0199"}).find("does not fit the lumen"), std::string::npos);
  EXPECT_NE(error_of({"instrument.port_s_m=1"}).find("instrument.port_s_m"), std::string::npos);
  const Scene plain = load_scene(test::source_path("scenes/aorta-bent.json"));
  EXPECT_THROW(run_navigation(plain, {}), InputError);
}

// The command writes a row per frame and a summary, and says where the wire went.
TEST(Navigation, TheCommandWritesItsFiles) {
  const std::filesystem::path dir = test::fresh_test_dir();
  const test::CliCapture r =
      test::run_cli_captured({"-q", "navigate", test::source_path(kAorta), "--out", dir.string(), "--set",
                              "instrument.drive=[[0,0.01,0],[0.1,0.012,0]]"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("12.0 mm in"), std::string::npos) << r.out;
  EXPECT_TRUE(std::filesystem::exists(dir / "instrument.csv"));
  EXPECT_TRUE(std::filesystem::exists(dir / "instrument_final.csv"));
  const json s = json::parse(std::ifstream(dir / "summary.json"));
  EXPECT_EQ(s["frames"].get<int>(), 11);
  EXPECT_EQ(s["wall"], "rigid");
  EXPECT_DOUBLE_EQ(s["final"]["inserted_m"].get<double>(), 0.012);
}

}  // namespace
}  // namespace vascsim
