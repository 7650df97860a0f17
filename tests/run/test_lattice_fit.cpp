// geometry.fit_lattice_to_patch (geometry/lattice_fit): the lattice's counts around and along the vessel
// chosen so that the first wall patch's strips ("strips"), or its nodes' span ("edges"), are the extent
// asked.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "support/run_helpers.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/core/json_file.hpp"
#include "vascsim/run/simulation.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim {
namespace {

const nlohmann::json& patch_report(const Simulation& sim) {
  for (const auto& s : sim.region_selections())
    if (s.name == "indenter") return s.report;
  throw std::runtime_error("no indenter region");
}

// The bundled vein's +-15 deg x +-1 mm patch at 0.3 mm: the plain lattice (28 columns 12.9 deg apart, 68
// cross-sections 0.2985 mm apart) selects 38.6 deg and 1.79 mm (+28.6 % and -10.4 %, with warnings); the
// fitted one selects the asked 30 deg and 2 mm (1e-9: the counts make them exact up to rounding), without
// warnings, with counts within the 0.75-1.5 band around the plain ones.
TEST(LatticeFit, APatchSelectsTheAreaAsked) {
  nlohmann::json doc = read_json_file(test::source_path("scenes/vein-indent.json"), "scene", "a scene");
  doc["geometry"]["node_spacing_m"] = 0.3e-3;
  doc["discretization"]["max_growths"] = 10;
  doc["geometry"]["fit_lattice_to_patch"] = "none";  // the scene fits its lattice to the patch's edges
  const Simulation plain(parse_scene(doc, "vein.json"));
  const nlohmann::json& before = patch_report(plain);
  EXPECT_GT(before["selected"]["angle_deg"].get<double>(), 38.0);
  doc["geometry"]["fit_lattice_to_patch"] = "strips";
  const Simulation fitted(parse_scene(doc, "vein.json"));
  const nlohmann::json& after = patch_report(fitted);
  std::printf("[ lattice fit ] plain: %.3f deg x %.4f mm, %d nodes; fitted: %.3f deg x %.4f mm, %d nodes\n",
              before["selected"]["angle_deg"].get<double>(),
              1e3 * before["selected"]["length_m"].get<double>(),
              static_cast<int>(plain.discretization().num_nodes()),
              after["selected"]["angle_deg"].get<double>(), 1e3 * after["selected"]["length_m"].get<double>(),
              static_cast<int>(fitted.discretization().num_nodes()));
  EXPECT_NEAR(after["selected"]["angle_deg"].get<double>(), 30.0, 1e-9);
  EXPECT_NEAR(after["selected"]["length_m"].get<double>(), 2e-3, 1e-9 * 2e-3);
  EXPECT_NEAR(after["selected"]["angle_center_deg"].get<double>(), 90.0, 1e-9);
  EXPECT_TRUE(after["warnings"].empty()) << after["warnings"].dump();
  const double ratio =
      static_cast<double>(fitted.discretization().num_nodes()) / plain.discretization().num_nodes();
  EXPECT_GT(ratio, 0.75 * 0.75);
  EXPECT_LT(ratio, 1.5 * 1.5);
}

// Fitted to the edges, the outermost selected nodes lie on the patch's edges: the nodes span the asked 30 deg
// and 2 mm (1e-9 again), reported as measured by span, without warnings; the strips reach half a step beyond
// them.
TEST(LatticeFit, APatchsNodesReachItsEdges) {
  nlohmann::json doc = read_json_file(test::source_path("scenes/vein-indent.json"), "scene", "a scene");
  doc["geometry"]["node_spacing_m"] = 0.3e-3;
  doc["discretization"]["max_growths"] = 10;
  doc["geometry"]["fit_lattice_to_patch"] = "edges";
  const Simulation fitted(parse_scene(doc, "vein.json"));
  const nlohmann::json& r = patch_report(fitted);
  const auto& sel = r["selected"];
  std::printf("[ lattice fit ] edges: %.3f deg x %.4f mm, %d columns x %d cross-sections, %d nodes\n",
              sel["angle_deg"].get<double>(), 1e3 * sel["length_m"].get<double>(), sel["columns"].get<int>(),
              sel["cross_sections"].get<int>(), static_cast<int>(fitted.discretization().num_nodes()));
  EXPECT_EQ(sel["measured_as"], "edges");
  EXPECT_NEAR(sel["angle_deg"].get<double>(), 30.0, 1e-9);
  EXPECT_NEAR(sel["length_m"].get<double>(), 2e-3, 1e-9 * 2e-3);
  EXPECT_NEAR(sel["angle_center_deg"].get<double>(), 90.0, 1e-9);
  EXPECT_NEAR((sel["columns"].get<int>() - 1) * sel["lattice_angle_step_deg"].get<double>(), 30.0, 1e-9);
  EXPECT_TRUE(r["warnings"].empty()) << r["warnings"].dump();
}

// A patch of zero width and length (one column, one cross-section) fitted to its edges selects the single
// outer node on its centre: the counts put a column and a cross-section there.
TEST(LatticeFit, AZeroWidthPatchSelectsTheNodeAtItsCentre) {
  nlohmann::json doc = read_json_file(test::source_path("scenes/vein-indent.json"), "scene", "a scene");
  doc["geometry"]["node_spacing_m"] = 0.3e-3;
  doc["discretization"]["max_growths"] = 10;
  doc["geometry"]["fit_lattice_to_patch"] = "edges";
  doc["regions"][2]["select"]["angle_half_width_deg"] = 0.0;
  doc["regions"][2]["select"]["z_half_length_m"] = 0.0;
  const Simulation fitted(parse_scene(doc, "vein.json"));
  const nlohmann::json& r = patch_report(fitted);
  EXPECT_EQ(r["nodes"].get<int>(), 1) << r.dump();
  EXPECT_NEAR(r["selected"]["angle_center_deg"].get<double>(), 90.0, 1e-9);
  EXPECT_NEAR(r["selected"]["s_center_m"].get<double>(), 10e-3, 1e-12);
}

// Without a wall patch, with the phase set by hand, or with a value that is not a fit, the key is an input
// error naming it.
TEST(LatticeFit, NeedsAPatchAndItsOwnPhase) {
  nlohmann::json doc = read_json_file(test::source_path("scenes/vein-indent.json"), "scene", "a scene");
  doc["geometry"]["fit_lattice_to_patch"] = "edges";
  doc["geometry"]["lattice_angle_deg"] = 10.0;
  EXPECT_THROW(parse_scene(doc, "vein.json"), InputError);
  doc["geometry"].erase("lattice_angle_deg");
  doc["regions"].erase(2);
  try {
    parse_scene(doc, "vein.json");
    FAIL() << "fitted to no patch";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("fit_lattice_to_patch"), std::string::npos) << e.what();
  }
  nlohmann::json boolean = read_json_file(test::source_path("scenes/vein-indent.json"), "scene", "a scene");
  boolean["geometry"]["fit_lattice_to_patch"] = true;
  EXPECT_THROW(parse_scene(boolean, "vein.json"), InputError);
}

}  // namespace
}  // namespace vascsim
