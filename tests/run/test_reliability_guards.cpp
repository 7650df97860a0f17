// Numerical guards and interrupts of a run (docs/reliability.md): inverted material is found in any
// configuration (model/inversion_check), a dynamic model that crushes the body stops with exit 3 naming the
// step, and a run interrupted mid-way leaves summary.json, probes.csv and the .pvd index complete up to the
// last step it finished.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "support/cli_capture.hpp"
#include "support/scenes.hpp"
#include "vascsim/core/interrupt.hpp"
#include "vascsim/model/inversion_check.hpp"
#include "vascsim/run/runner.hpp"
#include "vascsim/run/simulation.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

/// The shared tiny box (support/scenes.hpp) writing its VTK frames.
json tiny_box(double push_m, int load_steps) {
  json scene = test::tiny_box(push_m, load_steps);
  scene["output"] = {{"vtk", true}};
  return scene;
}

TEST(InversionCheck, FindsEveryInvertedTetAndNode) {
  const Scene scene = parse_scene(tiny_box(1e-5, 1), "tiny-box.json");
  Simulation sim(scene);
  const Vec3Array& X = sim.discretization().rest_positions();
  EXPECT_FALSE(check_inversion(sim.problem(), X).any());
  // A mirror image: every tetrahedron and every node's F (det -1) inverted.
  Vec3Array mirrored = X;
  for (Vec3& p : mirrored) p.x() = -p.x();
  const InversionReport r = check_inversion(sim.problem(), mirrored);
  EXPECT_EQ(r.inverted_tets, static_cast<Index>(sim.discretization().tets().size()));
  EXPECT_EQ(r.inverted_nodes, sim.discretization().num_nodes());
  EXPECT_NEAR(r.min_det_f, -1.0,
              1e-12);  // a mirror is exactly linear: the MLS fit reproduces it to round-off
  EXPECT_EQ(r.first_tet, 0);
  EXPECT_EQ(r.first_node, 0);
}

TEST(InversionCheck, DynamicModelThatCrushesTheBodyStopsWithExit3NamingTheStep) {
  const fs::path dir = test::fresh_test_dir();
  // The top pushed 0.9 mm down at once: the explicit model moves it there in one substep, through the layers.
  json scene = tiny_box(0.9e-3, 1);
  scene["model"] = "explicit";
  scene["explicit"] = {{"duration_s", 2e-3}, {"output_interval_s", 1e-3}, {"ramp_time_s", 0.0}};
  const std::string file = test::write_file(dir / "crush.json", scene.dump());
  const test::CliCapture r = test::run_cli_captured({"run", file, "--out", (dir / "out").string()});
  EXPECT_EQ(r.code, 3) << r.err;
  ASSERT_EQ(r.messages.size(), 1u) << r.err;
  EXPECT_NE(r.messages[0].find("explicit: step 1 (t = 0.001 s"), std::string::npos) << r.messages[0];
  EXPECT_NE(r.messages[0].find("inverted"), std::string::npos) << r.messages[0];
}

TEST(RunInterrupt, StopsAtTheNextStepBoundaryWithCompleteFiles) {
  const fs::path out = test::fresh_test_dir() / "out";
  const Scene scene = parse_scene(tiny_box(1e-5, 4), "tiny-box.json");
  RunOptions options;
  options.out_dir = out;
  options.on_step = [](const StepRecord& r, int) {
    if (r.step == 1) request_interrupt();  // as Ctrl-C during step 2 would
  };
  const json summary = run_scene(scene, options);
  clear_interrupt();
  EXPECT_TRUE(summary["interrupted"].get<bool>());
  EXPECT_EQ(summary["steps"].size(), 2u) << "the rest state and step 1";
  const json written = json::parse(test::read_file(out / "summary.json"));
  EXPECT_EQ(written["steps"].size(), 2u);
  const std::string probes = test::read_file(out / "probes.csv");
  EXPECT_EQ(std::count(probes.begin(), probes.end(), '\n'), 3) << "header and two rows:\n" << probes;
  const std::string pvd = test::read_file(out / "vtk" / "nodes.pvd");
  EXPECT_NE(pvd.find("nodes_0001.vtu"), std::string::npos);
  EXPECT_EQ(pvd.find("nodes_0002.vtu"), std::string::npos);
  EXPECT_NE(pvd.rfind("</VTKFile>\n"), std::string::npos);
}

}  // namespace
}  // namespace vascsim
