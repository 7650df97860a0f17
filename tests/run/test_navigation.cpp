// A flexible instrument advanced through a vessel's lumen by a scene (run/navigation.hpp, `vascsim
// navigate`): it stays in the lumen, the hand's load balances the wall's, turning the proximal end turns the
// tip, and a scene that cannot be navigated says why.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
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

// An independent reference for the rod in a curved rigid tube: a straight wire fed without friction into a
// long arc of a torus. Once its tip is well in, each millimetre fed adds a millimetre of wire bent to the
// curvature kappa it has in the arc and shifts the rest along the arc unchanged, and frictionless contact
// does no work: the insertion force is the bending energy per length, EI kappa^2 / 2 (an energy balance,
// exact for the continuum; the straight leg is long enough that the arc's entry does not reach the port).
// kappa is measured on the rod (the circle through three nodes, the median over the arc's steady part) and
// must lie within the lumen's band, 1 / (R -+ c) for the clearance c = R_lumen - r (0.16 mm: +-0.3 %).
// Tolerances: 0.3 % on the median force of the steady frames and 0.5 % on each (the 1 mm edges passing the
// arc's entry move it by about +-0.15 %; the chords' curvature error is 2e-5).
TEST(Navigation, AStraightWireFedIntoAnArcNeedsItsBendingEnergyPerLength) {
  const json doc = json::parse(R"({
    "name": "torus",
    "model": "quasi_static",
    "geometry": { "type": "vessel",
                  "centerline": { "type": "bent", "radius_of_curvature_m": 0.05, "angle_deg": 270,
                                  "leg_length_m": 0.05 },
                  "outer_radius_m": 0.8e-3, "wall_thickness_m": 0.2e-3, "node_spacing_m": 0.2e-3 },
    "regions": [ { "name": "end", "select": { "type": "cylinder_end", "end": "start" }, "bc": { "type": "fixed" } } ],
    "instrument": { "preset": "guidewire-035", "length_m": 0.3, "friction": 0, "tip": { "shape": "straight" },
                    "drive": [[0, 0.005, 0], [1, 0.205, 0]] }
  })");
  const Scene scene = parse_scene(doc, "torus.json");
  const NavigationResult r = run_navigation(scene, {});
  const rod::RodSection& s = scene.instrument->section;
  const double ei = s.youngs_modulus_pa * std::numbers::pi * std::pow(s.outer_diameter_m, 4) / 64.0;
  // The rod's radius of curvature in the arc's steady part (30 to 120 mm past the arc's start).
  const Centerline c = build_centerline(scene.geometry.centerline);
  const Vec3Array& x = r.final_positions_m;
  std::vector<double> radii;
  for (std::size_t i = 1; i + 1 < x.size(); ++i) {
    const double at = c.closest_arc_length(x[i]);
    if (at < 0.08 || at > 0.17) continue;
    const Vec3 a = x[i - 1] - x[i], b = x[i + 1] - x[i];
    radii.push_back(a.norm() * b.norm() * (a - b).norm() / (2.0 * a.cross(b).norm()));
  }
  ASSERT_GT(radii.size(), 50u);
  std::nth_element(radii.begin(), radii.begin() + radii.size() / 2, radii.end());
  const double radius = radii[radii.size() / 2];
  const double clearance = (0.8e-3 - 0.2e-3) - 0.5 * s.outer_diameter_m;
  EXPECT_GT(radius, 0.05 - clearance - 1e-6);
  EXPECT_LT(radius, 0.05 + clearance + 1e-6);
  const double expected = ei / (2.0 * radius * radius);  // 0.3675 N
  std::vector<double> steady;
  for (const NavigationFrame& f : r.frames)
    if (f.inserted_m > 0.15) {
      EXPECT_TRUE(f.converged) << f.inserted_m;
      EXPECT_NEAR(f.insertion_force_n, expected, 5e-3 * expected) << f.inserted_m * 1e3 << " mm in";
      steady.push_back(f.insertion_force_n);
    }
  ASSERT_GT(steady.size(), 20u);
  std::nth_element(steady.begin(), steady.begin() + steady.size() / 2, steady.end());
  const double median = steady[steady.size() / 2];
  std::printf(
      "[ navigation ] rod's radius in the arc %.5g mm; steady insertion force %.6g N, EI / (2 R^2) = %.6g N "
      "(%+.3f %%)\n",
      radius * 1e3, median, expected, 100.0 * (median / expected - 1.0));
  EXPECT_NEAR(median, expected, 3e-3 * expected);
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
  EXPECT_NE(error_of({"instrument.outer_diameter_m=0.0199"}).find("does not fit the lumen"),
            std::string::npos);
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
