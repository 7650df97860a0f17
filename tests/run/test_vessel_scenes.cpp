// Vessel geometries in scenes (docs/scene-format.md "vessel"): centre-line sweeps with region
// selectors along the arc length and angle, the tube as a special case, surface patches, and the
// MLS-mapped surface series a run writes.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>

#include "vascsim/core/error.hpp"
#include "vascsim/run/discretization_setup.hpp"
#include "vascsim/run/runner.hpp"
#include "vascsim/run/simulation.hpp"
#include "vascsim/scene/scene.hpp"

namespace {

using nlohmann::json;
using namespace vascsim;

// A coarse 120-degree bend (outer radius 1.5 mm, wall 0.4 mm, 3 layers) with clamped ends and an
// inward push on the outer wall at mid-length, theta = 90 (out of the bend plane).
json bent_vessel() {
  return json::parse(R"({
    "name": "bent",
    "geometry": { "type": "vessel",
                  "centerline": { "type": "bent", "radius_of_curvature_m": 6e-3, "angle_deg": 120,
                                  "leg_length_m": 1e-3 },
                  "outer_radius_m": 1.5e-3, "wall_thickness_m": 0.4e-3, "node_spacing_m": 0.4e-3 },
    "discretization": { "max_growths": 10 },
    "regions": [
      { "name": "end_start", "select": { "type": "cylinder_end", "end": "start" }, "bc": { "type": "fixed" } },
      { "name": "end_finish", "select": { "type": "cylinder_end", "end": "end" }, "bc": { "type": "fixed" } },
      { "name": "indenter",
        "select": { "type": "wall_patch", "surface": "outer", "angle_center_deg": 90, "angle_half_width_deg": 25,
                    "s_center_fraction": 0.5, "s_half_length_m": 0.5e-3 },
        "bc": { "type": "displacement", "direction": "inward", "magnitude_m": 1e-4 } }
    ],
    "quasi_static": { "load_steps": 2, "rel_tolerance": 1e-6 },
    "output": { "surface": true }
  })");
}

struct Built {
  Body body;
  std::unique_ptr<Discretization> disc;
  std::vector<Region> regions;
};

Built build(const json& doc) {
  const Scene sc = parse_scene(doc, "in-memory.json");
  Built b{build_body(sc.geometry), nullptr, {}};
  b.disc = std::make_unique<Discretization>(b.body.cloud, sc.material, discretization_options(sc, b.body));
  b.regions = build_regions(sc, *b.disc, b.body);
  return b;
}

TEST(VesselScene, BentSelectorsFollowTheCentreline) {
  const Built b = build(bent_vessel());
  const WallCoordinates& w = *b.body.wall;
  const Centerline& cl = *w.centerline;
  const double R = 1.5e-3, L = cl.length();
  const Vec3Array& X = b.disc->rest_positions();
  // The clamped ends are the full end cross-sections: in the normal plane of the end point.
  for (int e = 0; e < 2; ++e) {
    const Region& r = b.regions[static_cast<std::size_t>(e)];
    const double s = e == 0 ? 0.0 : L;
    for (Index i : r.nodes)
      EXPECT_NEAR((X[static_cast<std::size_t>(i)] - cl.position(s)).dot(cl.tangent(s)), 0.0, 1e-9 * R);
    EXPECT_EQ(r.nodes.size(), b.regions[0].nodes.size());
  }
  // The patch: outer-wall nodes (distance R from the centre-line point of their section) within the
  // arc-length window and angle; the push is minus the outward radial at the patch centre, which for
  // theta = 90 deg is minus B: perpendicular to the bend plane (x-z), i.e. along -y or +y.
  const Region& ind = b.regions[2];
  ASSERT_FALSE(ind.nodes.empty());
  for (Index i : ind.nodes) {
    const auto k = static_cast<std::size_t>(i);
    EXPECT_NEAR((X[k] - cl.position(w.s_m[k])).norm(), R, 1e-9 * R);
    EXPECT_LE(std::abs(w.s_m[k] - 0.5 * L), 0.5e-3 + 1e-12);
  }
  const Vec3 d = ind.displacement_m / 1e-4;
  EXPECT_NEAR(std::abs(d.y()), 1.0, 1e-9);  // tolerance: frame transport error of the RMF, ~1e-12
  EXPECT_NEAR(d.norm(), 1.0, 1e-12);
}

TEST(VesselScene, StraightVesselEqualsTheTube) {
  json tube = json::parse(R"({
    "geometry": { "type": "tube", "outer_radius_m": 1.5e-3, "wall_thickness_m": 0.4e-3, "length_m": 2.4e-3,
                  "node_spacing_m": 0.4e-3 },
    "regions": [
      { "name": "a", "select": { "type": "cylinder_end", "end": "start" }, "bc": { "type": "fixed" } },
      { "name": "b", "select": { "type": "wall_patch", "angle_center_deg": 45, "angle_half_width_deg": 30,
                                 "z_center_m": 1.2e-3, "z_half_length_m": 0.4e-3 },
        "bc": { "type": "displacement", "direction": "inward", "magnitude_m": 1e-4 } }
    ]
  })");
  json vessel = tube;
  vessel["geometry"] =
      json::parse(R"({ "type": "vessel", "centerline": { "type": "straight", "length_m": 2.4e-3 },
    "outer_radius_m": 1.5e-3, "wall_thickness_m": 0.4e-3, "node_spacing_m": 0.4e-3 })");
  vessel["regions"][1]["select"].erase("z_center_m");
  vessel["regions"][1]["select"].erase("z_half_length_m");
  vessel["regions"][1]["select"]["s_center_fraction"] = 0.5;
  vessel["regions"][1]["select"]["s_half_length_m"] = 0.4e-3;
  const Built t = build(tube), v = build(vessel);
  ASSERT_EQ(t.body.cloud.positions.size(), v.body.cloud.positions.size());
  for (std::size_t r = 0; r < 2; ++r) {
    EXPECT_EQ(t.regions[r].nodes, v.regions[r].nodes);
    // 1e-12: the two generators differ only by the rounding of the frame (cos, sin) products.
    EXPECT_LT((t.regions[r].displacement_m - v.regions[r].displacement_m).norm(), 1e-12 * 1e-4);
  }
  const double th = 45.0 * std::numbers::pi / 180.0;
  EXPECT_LT((t.regions[1].displacement_m - (-1e-4) * Vec3(std::cos(th), std::sin(th), 0.0)).norm(),
            1e-12 * 1e-4);
  // The tube's render surface: 2 walls and 2 end rings, closed (every edge in two triangles).
  ASSERT_TRUE(t.body.surface.has_value());
  std::map<std::pair<Index, Index>, int> edges;
  for (const auto& tri : t.body.surface->triangles)
    for (int e = 0; e < 3; ++e) ++edges[std::minmax(tri[e], tri[(e + 1) % 3])];
  for (const auto& [edge, count] : edges) EXPECT_EQ(count, 2);
}

TEST(VesselScene, SurfacePatchSelectsTheOuterShellAroundAPoint) {
  json doc = bent_vessel();
  doc["geometry"]["centerline"] = {{"type", "straight"}, {"length_m", 3.2e-3}};
  doc["regions"][2]["select"] = {
      {"type", "surface_patch"}, {"centre_m", {0.0, 1.5e-3, 1.6e-3}}, {"radius_m", 0.7e-3}};
  const Built b = build(doc);
  const Region& ind = b.regions[2];
  ASSERT_GT(ind.nodes.size(), 3u);
  for (Index i : ind.nodes) {
    const Vec3& p = b.disc->rest_positions()[static_cast<std::size_t>(i)];
    EXPECT_NEAR(std::hypot(p.x(), p.y()), 1.5e-3, 1e-9);  // outer shell only
    EXPECT_LE((p - Vec3(0.0, 1.5e-3, 1.6e-3)).norm(), 0.7e-3 + 1e-9);
  }
  // The patch is symmetric about the y-z plane, so the mean outward normal is +y: inward is -y
  // (tolerance: the lattice is symmetric to rounding).
  EXPECT_LT((ind.displacement_m / 1e-4 - Vec3(0, -1, 0)).norm(), 1e-6);
}

TEST(VesselScene, CentrelineSelectorsOnABoxFailClearly) {
  json doc = bent_vessel();
  doc["geometry"] = {
      {"type", "box"}, {"min_m", {0, 0, 0}}, {"max_m", {1e-3, 1e-3, 1e-3}}, {"node_spacing_m", 5e-4}};
  doc["regions"] = json::array({bent_vessel()["regions"][2]});
  doc["regions"][0]["select"] = {{"type", "surface_patch"}, {"centre_m", {0, 0, 0}}, {"radius_m", 1e-3}};
  try {
    build(doc);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("needs a vessel geometry"), std::string::npos) << e.what();
  }
}

TEST(VesselScene, BadCentrelinesAreInputErrors) {
  const std::vector<std::pair<json, std::string>> cases = {
      {{{"type", "helix"}}, "geometry.centerline.type"},
      {{{"type", "bent"}, {"angle_deg", 90}}, "geometry.centerline.radius_of_curvature_m"},
      {{{"type", "s"}, {"radius_of_curvature_m", 1e-2}, {"angle_deg", 200}}, "geometry.centerline.angle_deg"},
      {{{"type", "polyline"}, {"points_m", {{0, 0, 0}}}}, "geometry.centerline.points_m"},
      {{{"type", "polyline"}, {"points_m", {{0, 0, 0}, {0, 1}}}}, "geometry.centerline.points_m"},
  };
  for (const auto& [line, key] : cases) {
    json doc = bent_vessel();
    doc["geometry"]["centerline"] = line;
    try {
      parse_scene(doc, "in-memory.json");
      ADD_FAILURE() << "expected InputError for " << line.dump();
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("key '" + key + "'"), std::string::npos) << e.what();
    }
  }
  // A bend tighter than the vessel radius is found when the geometry is built.
  json doc = bent_vessel();
  doc["geometry"]["centerline"]["radius_of_curvature_m"] = 1e-3;
  EXPECT_THROW(build(doc), InputError);
}

TEST(VesselScene, RunWritesTheMappedSurfaceSeries) {
  const auto dir = std::filesystem::path(testing::TempDir()) / "vascsim-vessel-surface";
  std::filesystem::remove_all(dir);
  RunOptions opt;
  opt.out_dir = dir;
  const auto summary = run_scene(parse_scene(bent_vessel(), "bent.json"), opt);
  EXPECT_EQ(summary["outputs"]["surface"], "vtk/surface.pvd");
  EXPECT_TRUE(std::filesystem::exists(dir / "vtk" / "surface.pvd"));
  for (const char* f : {"surface_0000.vtu", "surface_0001.vtu", "surface_0002.vtu"})
    EXPECT_TRUE(std::filesystem::exists(dir / "vtk" / f)) << f;
  const auto& map = summary["surface_map"];
  EXPECT_LE(map["max_cond"].get<double>(), 1e3);  // docs/model/20-mls-map.md section 20.2 guard
  EXPECT_GE(map["min_support"].get<int>(), 8);
  EXPECT_EQ(summary["unconverged_steps"], 0);
}

}  // namespace
