// Regions that do what they say (issue 14): every selector reports what it selected beside what was asked
// (summary.json "regions"), warns naming the region and the key when they differ by more than
// kSelectionTolerance, and the tube/vessel lattice is turned so that a wall patch's centre lies on a
// lattice line, so a +-15 deg patch is 5 columns wherever it is centred.

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

#include <memory>
#include <string>
#include <vector>

#include "vascsim/core/error.hpp"

#include "vascsim/run/body_builder.hpp"
#include "vascsim/run/discretization_setup.hpp"
#include "vascsim/run/region_builder.hpp"
#include "vascsim/run/region_report.hpp"
#include "vascsim/run/simulation.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim {
namespace {

using json = nlohmann::json;

// The vein's cross-section at its default 0.15 mm (57 columns of 6.316 deg, 3 layers), 4 mm long, ends
// clamped, a +-15 deg x +-0.6 mm outer patch at mid-length pushed `push_m` inward in one step.
constexpr double kStep = 360.0 / 57;

json vein(double centre_deg, double push_m = 0.0) {
  json doc = json::parse(R"({
    "name": "patch-phase", "model": "quasi_static",
    "geometry": { "type": "tube", "outer_radius_m": 1.5e-3, "wall_thickness_m": 0.3e-3, "length_m": 4e-3,
                  "node_spacing_m": 0.15e-3 },
    "material": { "youngs_modulus_pa": 0.5e6, "poisson_ratio": 0.45 },
    "regions": [
      { "name": "end_start", "select": { "type": "cylinder_end", "end": "start" }, "bc": { "type": "fixed" } },
      { "name": "end_finish", "select": { "type": "cylinder_end", "end": "end" }, "bc": { "type": "fixed" } },
      { "name": "indenter", "select": { "type": "wall_patch", "surface": "outer", "angle_center_deg": 90,
          "angle_half_width_deg": 15, "s_center_m": 2e-3, "s_half_length_m": 0.6e-3 },
        "bc": { "type": "displacement", "direction": "inward", "magnitude_m": 0 } } ],
    "quasi_static": { "load_steps": 1, "rel_tolerance": 1e-8 }
  })");
  doc["regions"][2]["select"]["angle_center_deg"] = centre_deg;
  doc["regions"][2]["bc"]["magnitude_m"] = push_m;
  return doc;
}

// The selection reports without building a model (what Simulation does at set-up, minus the solver).
struct Selected {
  Scene scene;
  Body body;
  std::unique_ptr<Discretization> disc;
  std::vector<RegionSelection> reports;
  explicit Selected(const json& doc)
      : scene(parse_scene(doc, "patch-phase")), body(build_body(scene.geometry)) {
    disc = std::make_unique<Discretization>(body.cloud, scene.material, discretization_options(scene, body));
    reports = describe_selections(scene, *disc, body, build_regions(scene, *disc, body));
  }
  const RegionSelection& indenter() const { return reports.at(2); }
};

// The issue's example: a centre half-way between two angles of the plain lattice (columns 14 and 15, at
// 88.4 and 94.7 deg). Turned onto it, the patch is 5 whole columns centred on the asked angle: 31.6 deg for
// the asked 30 (+5 %, inside the 10 % tolerance), no warning.
TEST(RegionSelection, PatchBetweenLatticeAnglesIsAlignedAndReported) {
  const double centre = 14.5 * kStep;
  const Selected sel(vein(centre));
  const json& r = sel.indenter().report;
  EXPECT_EQ(r["selector"], "wall_patch");
  EXPECT_EQ(r["selected"]["columns"], 5);
  EXPECT_NEAR(r["selected"]["angle_deg"].get<double>(), 5 * kStep, 1e-9);
  EXPECT_NEAR(r["selected"]["angle_center_deg"].get<double>(), centre, 1e-9);
  EXPECT_NEAR(r["asked"]["angle_deg"].get<double>(), 30.0, 1e-12);
  // Axially: 28 cross-sections 4/27 mm apart; |s - 2 mm| <= 0.6 mm holds for sections 10-17, 8 strips =
  // 1.185 mm for the asked 1.2 mm, centred on 2 mm.
  const double ds = 4e-3 / 27;
  EXPECT_EQ(r["selected"]["cross_sections"], 8);
  EXPECT_NEAR(r["selected"]["length_m"].get<double>(), 8 * ds, 1e-12);
  EXPECT_NEAR(r["selected"]["s_center_m"].get<double>(), 2e-3, 1e-12);
  EXPECT_EQ(r["nodes"], 5 * 8);
  // A straight wall: the asked area is r (2 w) (2 l) (midpoint rule exact to rounding), the selected one
  // the strips' area on the faceted lattice surface (chords: cos of half a column below the arc).
  const double arc = 1.5e-3 * std::numbers::pi / 180.0;
  EXPECT_NEAR(r["asked"]["area_m2"].get<double>(), arc * 30.0 * 1.2e-3, 1e-9 * arc * 30.0 * 1.2e-3);
  const double strips = arc * 5 * kStep * 8 * ds;
  EXPECT_NEAR(r["selected"]["area_m2"].get<double>() / strips, 1.0, 2e-3);
  EXPECT_TRUE(sel.indenter().warnings.empty()) << sel.indenter().warnings.front();
}

// Breaking the alignment (geometry.lattice_angle_deg = 0, the plain lattice) selects 4 columns, 25.3 deg of
// the asked 30 (-15.8 %): the report says so and the warning names the region and the key.
TEST(RegionSelection, UnalignedPatchWarnsNamingRegionAndKey) {
  json doc = vein(14.5 * kStep);
  doc["geometry"]["lattice_angle_deg"] = 0;
  const Selected sel(doc);
  const RegionSelection& r = sel.indenter();
  EXPECT_EQ(r.report["selected"]["columns"], 4);
  EXPECT_NEAR(r.report["selected"]["angle_deg"].get<double>(), 4 * kStep, 1e-9);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings.front().find("region 'indenter'"), std::string::npos) << r.warnings.front();
  EXPECT_NE(r.warnings.front().find("angle_half_width_deg"), std::string::npos) << r.warnings.front();
  EXPECT_EQ(r.report["warnings"].size(), r.warnings.size());
  // The clamped ends report their node count (a full cross-section: 57 columns x 3 layers).
  EXPECT_EQ(sel.reports.at(0).report["nodes"], 57 * 3);
}

// A patch wider than its lattice resolves (+-4 deg on 6.3 deg columns: one column, 6.3 deg for 8) warns even
// when aligned; a surface patch reports its area against the flat disc.
TEST(RegionSelection, NarrowPatchAndSurfacePatchReportTheirMismatch) {
  json doc = vein(90.0);
  doc["regions"][2]["select"]["angle_half_width_deg"] = 4.0;
  const Selected narrow(doc);
  EXPECT_EQ(narrow.indenter().report["selected"]["columns"], 1);
  EXPECT_FALSE(narrow.indenter().warnings.empty());
  doc["regions"][2]["select"] = json::parse(R"({ "type": "surface_patch", "surface": "outer",
      "centre_m": [0, 1.5e-3, 2e-3], "radius_m": 0.6e-3 })");
  const Selected disc_patch(doc);
  const json& r = disc_patch.indenter().report;
  const double asked = std::numbers::pi * 0.36e-6;
  EXPECT_NEAR(r["asked"]["area_m2"].get<double>(), asked, 1e-15);
  EXPECT_NEAR(r["selected"]["area_m2"].get<double>() / asked, 1.0, 0.21);  // inside the tolerance: no warning
  EXPECT_TRUE(disc_patch.indenter().warnings.empty());
}

// The input error of a region that selects nothing (build_regions, after the body is built).
std::string empty_selection_error(const json& doc) {
  const Scene scene = parse_scene(doc, "patch-phase");
  const Body body = build_body(scene.geometry);
  const Discretization disc(body.cloud, scene.material, discretization_options(scene, body));
  try {
    build_regions(scene, disc, body);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "every region selected nodes";
  return "";
}

// A region that selects nothing says why (it said only "selects no nodes"): the body's extent in the
// selector's own coordinates beside the window asked, and "these values look like millimetres" where the
// window divided by 1000 meets the body.
TEST(RegionSelection, ARegionThatSelectsNothingNamesTheBodysExtentAndItsWindow) {
  auto expect_has = [](const std::string& message, const std::vector<std::string>& parts, bool millimetres) {
    for (const std::string& p : parts)
      EXPECT_NE(message.find(p), std::string::npos) << "'" << p << "' in " << message;
    EXPECT_EQ(message.find(
                  "these values look like millimetres (divided by 1000 they meet the body): lengths are in "
                  "metres") != std::string::npos,
              millimetres)
        << message;
  };
  // The patch's centre and half-length typed in millimetres: s = 2 +- 0.6 m along a 4 mm tube.
  json doc = vein(90.0);
  doc["regions"][2]["select"]["s_center_m"] = 2.0;
  doc["regions"][2]["select"]["s_half_length_m"] = 0.6;
  expect_has(
      empty_selection_error(doc),
      {"patch-phase: key 'regions.2.select': region 'indenter' selects no nodes: its window is 90 +- 15 deg "
       "round the centre-line (angle_center_deg, angle_half_width_deg) and s = 2 +- 0.6 m along it",
       "the body's outer surface nodes lie at s = 0 .. 0.004 m"},
      true);
  // In metres on the body, but narrower than a column and between two (the plain lattice's 88.4 and 94.7
  // deg).
  doc = vein(90.0);
  doc["geometry"]["lattice_angle_deg"] = 0;
  doc["regions"][2]["select"]["angle_half_width_deg"] = 1.0;
  expect_has(empty_selection_error(doc),
             {"their column nearest 90 deg is 1.579 deg from it (a column every 6.316 deg)"}, false);
  // A box in millimetres, and one that misses the body in either unit.
  doc = vein(90.0);
  doc["regions"][2]["select"] =
      json::parse(R"({ "type": "box", "min_m": [-1, 1, 1.5], "max_m": [1, 2, 2.5] })");
  doc["regions"][2]["bc"] = {{"type", "fixed"}};
  expect_has(empty_selection_error(doc),
             {"its box [-1, 1, 1.5] .. [1, 2, 2.5] m (min_m, max_m) holds none of the body, whose nodes lie "
              "within [",
              ", 0] .. [", ", 0.004] m"},
             true);
  doc["regions"][2]["select"] = json::parse(R"({ "type": "box", "min_m": [10, 10, 10] })");
  expect_has(empty_selection_error(doc), {"its box [10, 10, 10] .. [inf, inf, inf] m"}, false);
  // A surface patch centred in millimetres.
  doc["regions"][2]["select"] =
      json::parse(R"({ "type": "surface_patch", "centre_m": [0, 1.5, 2], "radius_m": 0.6 })");
  expect_has(
      empty_selection_error(doc),
      {"its sphere of radius 0.6 m (radius_m) round [0, 1.5, 2] m (centre_m) holds none of the body's outer "
       "surface nodes"},
      true);
}

double patch_force(const json& doc) {
  Simulation sim(parse_scene(doc, "patch-phase"));
  const StepRecord rec = sim.advance(1);
  EXPECT_TRUE(rec.report.converged);
  return rec.regions.at(2).force_n;
}

// The force a +-15 deg patch drives does not depend on where its centre falls relative to the plain lattice:
// centred on a lattice angle or between two, the aligned lattice is the same body turned, so the forces
// agree to the solver tolerance (1e-8: bound 1e-6). With the plain lattice (the break) they differ by the
// column the patch gains or loses: more than 5 % here.
TEST(RegionSelection, PatchForceDoesNotDependOnTheLatticePhaseSlow) {
  const double push = 0.2e-3;
  const double on_line = patch_force(vein(90.0, push)), between = patch_force(vein(14.5 * kStep, push));
  ASSERT_GT(on_line, 0.0);
  EXPECT_NEAR(between / on_line, 1.0, 1e-6);
  json plain_on = vein(14 * kStep, push), plain_between = vein(14.5 * kStep, push);
  plain_on["geometry"]["lattice_angle_deg"] = 0;
  plain_between["geometry"]["lattice_angle_deg"] = 0;
  const double f_on = patch_force(plain_on), f_between = patch_force(plain_between);
  std::printf(
      "[ patch    ] force at 0.2 mm: aligned %.5g / %.5g mN; plain lattice 5 columns %.5g, 4 columns %.5g "
      "mN\n",
      on_line * 1e3, between * 1e3, f_on * 1e3, f_between * 1e3);
  EXPECT_NEAR(f_on / on_line, 1.0, 1e-6);  // 14 columns: on a line of the plain lattice already
  EXPECT_GT(f_on / f_between - 1.0, 0.05);
}

}  // namespace
}  // namespace vascsim
