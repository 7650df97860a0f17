// `vascsim check` (a dry run) against `vascsim run`, and what a run says when something is wrong: check
// builds every bundled scene and reports it; where `run` fails on input or in its set-up, `check` fails with
// the same exit code and the same message; a run with unconverged steps exits with 4 and says so; a tool that
// never touches the tissue, load steps too large for the contact and xpbd far from its accurate range are
// each named in one warning line. In-process through run_cli.

#include <gtest/gtest.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "support/cli_capture.hpp"
#include "support/run_helpers.hpp"
#include "vascsim/app/cli.hpp"

namespace vascsim {
namespace {

namespace fs = std::filesystem;

using CliResult = test::CliCapture;

CliResult cli(const std::vector<std::string>& args) {
  return test::run_cli_captured(args);
}

fs::path test_dir() {
  return test::fresh_test_dir();
}

std::vector<std::string> with_sets(std::vector<std::string> args, const std::vector<std::string>& sets) {
  for (const auto& s : sets) {
    args.push_back("--set");
    args.push_back(s);
  }
  return args;
}

nlohmann::json read_json(const fs::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

// ------------------------------------------------------------------------------------------------------------
// check on every bundled scene (aorta-vmtk, 88k nodes and 6 GB, only in `make vessel-aorta-vmtk`): it builds,
// reports the body, every region with its nodes, every tool, and an estimate line, and the bundled tools all
// reach the tissue. "Slow": some scenes have 23k-25k nodes and the real-time ones build a sparse factor.

class BundledSceneSlow : public ::testing::TestWithParam<std::string> {};

TEST_P(BundledSceneSlow, CheckBuildsAndReports) {
  const fs::path dir = test_dir();
  const std::string scene = test::source_path(GetParam());
  const CliResult r = cli({"-q", "check", scene, "--json", (dir / "check.json").string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.out_has("  body      ")) << r.out;
  EXPECT_TRUE(r.out_has("  time      ")) << r.out;
  EXPECT_TRUE(r.out_has("nothing solved")) << r.out;
  const nlohmann::json report = read_json(dir / "check.json");
  const nlohmann::json scene_json = read_json(scene);
  EXPECT_GT(report["nodes"].get<int>(), 100);
  EXPECT_GT(report["memory"]["resident_after_build_bytes"].get<double>(), 1e6);
  ASSERT_EQ(report["regions"].size(), scene_json.value("regions", nlohmann::json::array()).size());
  for (const auto& region : report["regions"]) EXPECT_GT(region["nodes"].get<int>(), 0) << region;
  ASSERT_EQ(report["tools"].size(), scene_json.value("obstacles", nlohmann::json::array()).size());
  for (const auto& tool : report["tools"]) EXPECT_TRUE(tool["touches"].get<bool>()) << tool;
  // The bundled scenes are the examples users copy: each runs without a warning, on the model the project
  // recommends for its purpose (issue 44).
  EXPECT_TRUE(report["warnings"].empty()) << report["warnings"];
  EXPECT_FALSE(r.err_has("warning")) << r.err;
  EXPECT_FALSE(r.out_has("warning")) << r.out;
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, BundledSceneSlow,
    ::testing::Values("scenes/vein-indent.json", "scenes/cantilever.json", "scenes/hand-dorsal-vein.json",
                      "scenes/hand-dorsal-vein-catheter.json", "scenes/hand-dorsal-vein-catheter-graded.json",
                      "scenes/aorta-bent.json", "scenes/aorta-bent-graded.json",
                      "scenes/aorta-bent-catheter.json", "scenes/retinal-artery-twice-bent.json",
                      "scenes/retinal-artery-twice-bent-probe.json", "scenes/realtime/hand-dorsal-vein.json",
                      "scenes/realtime/hand-dorsal-vein-catheter.json", "scenes/realtime/aorta-bent.json",
                      "scenes/realtime/aorta-bent-probe.json",
                      "scenes/realtime/retinal-artery-twice-bent.json",
                      "scenes/realtime/retinal-artery-twice-bent-probe.json",
                      "scenes/navigation/aorta-bent-guidewire.json"),
    [](const ::testing::TestParamInfo<std::string>& info) {
      std::string name = info.param.substr(info.param.find('/') + 1);
      for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      return name;
    });

// ------------------------------------------------------------------------------------------------------------
// Where run fails before solving, check fails the same way: same exit code, same message line.

struct Broken {
  std::string what, scene;
  std::vector<std::string> sets;
  int code;            // the exit code both give
  std::string phrase;  // a piece of the message that names the fix
};

TEST(CheckCommand, FailsWhereRunFailsWithTheSameMessage) {
  const std::string tiny = test::source_path("tests/data/tiny-bent-vessel.json");
  const std::vector<Broken> cases = {
      {"unknown key", tiny, {"geometry.bogus=1"}, 2, "bogus"},
      {"a region that selects nothing",
       tiny,
       {"regions.2.select={\"type\":\"box\",\"min_m\":[1,1,1],\"max_m\":[2,2,2]}",
        "regions.2.bc={\"type\":\"fixed\"}"},
       2,
       "selects no nodes"},
      {"a vessel selector on a beam",
       test::source_path("scenes/cantilever.json"),
       {"regions.1.select={\"type\":\"cylinder_end\",\"end\":\"start\"}"},
       2,
       "needs a vessel geometry"},
      {"the discretisation guard",
       tiny,
       {"discretization.max_growths=0", "discretization.support_radius_factor=1.01"},
       3,
       "discretization.max_growths = "},
      {"the surface map's guard",
       tiny,
       {"mapping.max_growths=0", "mapping.support_radius_factor=1.5"},
       3,
       "mapping.max_growths = "},
      {"a body above the node limit without --yes",
       test::source_path("scenes/vein-indent.json"),
       {"geometry.outer_radius_m=0.015"},
       2,
       "--yes"},
      {"a missing trajectory",
       test::source_path("scenes/realtime/hand-dorsal-vein-catheter.json"),
       {"haptics.device.trajectory=no-such-trajectory.csv"},
       2,
       "no-such-trajectory.csv"},
  };
  const fs::path dir = test_dir();
  for (const Broken& c : cases) {
    SCOPED_TRACE(c.what);
    const CliResult run = cli(with_sets({"-q", "run", c.scene, "--out", (dir / "run").string()}, c.sets));
    const CliResult check = cli(with_sets({"-q", "check", c.scene}, c.sets));
    EXPECT_EQ(run.code, c.code) << run.err;
    EXPECT_EQ(check.code, run.code) << check.err;
    ASSERT_EQ(run.messages.size(), 1u) << run.err;
    ASSERT_EQ(check.messages.size(), 1u) << check.err;
    EXPECT_EQ(check.messages[0], run.messages[0]);
    EXPECT_NE(run.messages[0].find(c.phrase), std::string::npos) << run.messages[0];
  }
}

// A failed guard names the smallest value of its max_growths key that works: that value passes, one less
// fails.
void expect_guard_names_a_growth_that_works(const std::string& section, const std::string& factor) {
  const std::string tiny = test::source_path("tests/data/tiny-bent-vessel.json");
  auto check_with = [&](int growths) {
    return cli({"-q", "check", tiny, "--set", section + ".max_growths=" + std::to_string(growths), "--set",
                section + ".support_radius_factor=" + factor});
  };
  const CliResult failed = check_with(0);
  ASSERT_EQ(failed.code, 3) << failed.err;
  const std::string key = section + ".max_growths = ";
  const std::size_t at = failed.err.find(key);
  ASSERT_NE(at, std::string::npos) << failed.err;
  const int growths = std::stoi(failed.err.substr(at + key.size()));
  EXPECT_GT(growths, 0);
  const CliResult fixed = check_with(growths);
  EXPECT_EQ(fixed.code, 0) << fixed.err;
  EXPECT_EQ(check_with(growths - 1).code, 3) << "the smallest value that works is named";
}

TEST(CheckCommand, TheSurfaceMapGuardNamesAGrowthThatWorks) {
  expect_guard_names_a_growth_that_works("mapping", "1.5");
}

TEST(CheckCommand, TheSupportGuardNamesAGrowthThatWorks) {
  expect_guard_names_a_growth_that_works("discretization", "1.01");
}

// ------------------------------------------------------------------------------------------------------------
// Runs that finish but are wrong say so.

TEST(RunExitCode, UnconvergedStepsEndOnASummaryLineAndExitCode4) {
  const fs::path dir = test_dir();
  // One Newton iteration per load step cannot reach 1e-6 on a 0.2 mm push.
  const CliResult r = cli({"-q", "run", test::source_path("tests/data/tiny-bent-vessel.json"), "--out",
                           (dir / "out").string(), "--set", "quasi_static.max_newton_iterations=1", "--set",
                           "output.vtk=false", "--set", "output.surface=false"});
  EXPECT_EQ(r.code, 4) << r.out << r.err;
  EXPECT_TRUE(r.out_has("NOT CONVERGED: 2 of 2 steps")) << r.out;
  const nlohmann::json summary = read_json(dir / "out" / "summary.json");
  EXPECT_EQ(summary["unconverged_steps"].get<int>(), 2);
  // The same scene with its own settings converges and exits 0.
  const CliResult ok =
      cli({"-q", "run", test::source_path("tests/data/tiny-bent-vessel.json"), "--out", (dir / "ok").string(),
           "--set", "output.vtk=false", "--set", "output.surface=false"});
  EXPECT_EQ(ok.code, 0) << ok.out << ok.err;
  EXPECT_FALSE(ok.out_has("NOT CONVERGED")) << ok.out;
}

// A session whose frames reach the tissue but never hand on a contact force (here: one Newton step per frame
// and a hand-off bound no unconverged frame meets, as frames too slow for the hand do on a loaded machine)
// says so, instead of blaming the trajectory: the old message read "never touched the tissue" for a tool 10
// nodes deep.
TEST(RunWarnings, ASessionWhoseFramesNeverHandOnAContactForceSaysWhy) {
  const fs::path dir = test_dir();
  const CliResult run =
      cli({"run", test::source_path("tests/data/haptic-block.json"), "--out", (dir / "out").string(), "--set",
           "model=implicit", "--set", "implicit.max_newton_iterations=1", "--set",
           "implicit.rel_tolerance=1e-14", "--set", "implicit.handoff_max_residual=1e-14", "--set",
           "haptics.ticks_per_step=10", "--set", "haptics.duration_s=0.15"});
  // (Until 0.15 s, while the hand presses: once it holds, the single Newton steps converge within five
  // frames.)
  EXPECT_TRUE(
      run.out_has("warning: the tool 'catheter' reached the tissue, but none of the 16 frames handed on a "
                  "contact force (12 ended before converging)"))
      << run.out;
  EXPECT_FALSE(run.out_has("never touched")) << run.out;
}

// A soak drives the tool with its own wandering device, not the scene's trajectory: nothing may be said of
// that trajectory (the old session judged it and told a soak of the real-time vein that its tool "will never
// touch the tissue" and to "check the positions of the trajectory").
TEST(RunWarnings, ARealtimeSoakDoesNotJudgeATrajectoryItDoesNotFollow) {
  const fs::path dir = test_dir();
  const CliResult soak = cli({"soak", test::source_path("scenes/realtime/hand-dorsal-vein-catheter.json"),
                              "--seconds", "1", "--out", (dir / "soak").string()});
  EXPECT_EQ(soak.code, 0) << soak.out << soak.err;
  EXPECT_FALSE(soak.err_has("will never touch")) << soak.err;
  EXPECT_FALSE(soak.out_has("check the positions of the trajectory")) << soak.out;
  EXPECT_FALSE(soak.err_has("check the positions of the trajectory")) << soak.err;
}

// The soak's random hand (up to 1.4 mm deep, +-1 mm across, a waypoint every 0.5 s: up to 9 mm/s) on the
// real-time vein, with its tools on the wall's surface (the scene's contact) and at the nodes: the wall stays
// whole and the tissue's force reaches the hand. At the nodes with the tool placed at the device's pose every
// frame (implicit.realtime_tool_step 0) the frames the budget stopped fell behind it, the nodes it entered
// were projected through the wall (tetrahedra inverted at the first contacts, within the first second), and
// no frame handed on a force; on the surface, before a frame that starts from a wall thrown off went back to
// the last one that handed on, every soak ended in a non-finite residual within its first second of contact
// (exit 3).
TEST(RunWarnings, ARealtimeSoakKeepsTheWallWholeUnderARandomHand) {
  const fs::path dir = test_dir();
  for (const char* surface : {"embedded", "nodes"}) {
    SCOPED_TRACE(surface);
    const fs::path out = dir / (std::string("soak-") + surface);
    const CliResult soak =
        cli({"soak", test::source_path("scenes/realtime/hand-dorsal-vein-catheter.json"), "--seconds", "3",
             "--seed", "1", "--set", std::string("contact.surface=") + surface, "--out", out.string()});
    ASSERT_EQ(soak.code, 0) << soak.out << soak.err;
    const nlohmann::json summary = read_json(out / "summary.json");
    EXPECT_EQ(summary["inverted_steps"].get<int>(), 0) << soak.err;
    EXPECT_GT(summary["haptics"]["max_force_on_tool_n"].get<double>(), 0.0) << soak.err;
    EXPECT_FALSE(soak.err_has("handed on a contact force")) << soak.err;
  }
}

TEST(RunWarnings, AToolThatNeverTouchesIsNamedUpFrontAndAtTheEnd) {
  const fs::path dir = test_dir();
  const std::string tiny = test::source_path("tests/data/tiny-catheter.json");
  // The tip typed in millimetres: 1.6 m above the vessel.
  const std::vector<std::string> sets = {"obstacles.0.tip_m=[0,1.6,3]", "output.surface=false"};
  const CliResult check = cli(with_sets({"check", tiny}, sets));
  EXPECT_EQ(check.code, 0) << check.err;
  EXPECT_TRUE(check.out_has("tool 'catheter' will never touch the tissue")) << check.out;
  const CliResult run = cli(with_sets({"run", tiny, "--out", (dir / "out").string()}, sets));
  EXPECT_TRUE(run.err_has("[warning] tool 'catheter' will never touch the tissue")) << run.err;
  EXPECT_TRUE(run.out_has("warning: the tool 'catheter' never touched the tissue")) << run.out;
  // Nothing loads the vessel, so every step is the rest state: converged at once, not iterated on the
  // rounding of the rest state's forces until Newton gives up (NewtonEquilibrium's force floor).
  EXPECT_EQ(run.code, 0) << run.out << run.err;
  EXPECT_FALSE(run.out_has("NOT CONVERGED")) << run.out;
  // Where it does reach the tissue, neither warning.
  const CliResult touching = cli({"check", tiny, "--set", "output.surface=false"});
  EXPECT_FALSE(touching.out_has("never touch")) << touching.out;
  EXPECT_TRUE(touching.out_has("catheter: reaches the tissue")) << touching.out;
}

TEST(RunWarnings, ContactLoadStepsThatDoNotConvergeNameTheKey) {
  const fs::path dir = test_dir();
  // One load step for the whole 0.6 mm press with few Newton iterations: the contact set changes too much.
  const CliResult r = cli({"-q", "run", test::source_path("tests/data/tiny-catheter.json"), "--out",
                           (dir / "out").string(), "--set", "quasi_static.load_steps=1", "--set",
                           "quasi_static.max_newton_iterations=3", "--set", "output.surface=false"});
  EXPECT_EQ(r.code, 4) << r.out << r.err;
  EXPECT_TRUE(r.out_has("did not converge with a tool in contact")) << r.out;
  EXPECT_TRUE(r.out_has("quasi_static.load_steps, now 1")) << r.out;
}

TEST(RunWarnings, XpbdOnAThinStiffWallIsNamedWithTheMeasuredDeficit) {
  // The vein wall at 0.3 mm spacing with xpbd's 8 substeps of 1/8 ms: q = (h c_p / spacing)^2 is about 310.
  const CliResult check = cli({"check", test::source_path("tests/data/tiny-catheter.json"), "--set",
                               "model=xpbd", "--set", "output.surface=false"});
  EXPECT_EQ(check.code, 0) << check.err;
  EXPECT_TRUE(check.out_has("xpbd is far off at these settings")) << check.out;
  EXPECT_TRUE(check.out_has("96.6 % too low")) << check.out;
  // quasi_static on the same scene: no such warning.
  const CliResult qs =
      cli({"check", test::source_path("tests/data/tiny-catheter.json"), "--set", "output.surface=false"});
  EXPECT_FALSE(qs.out_has("far off")) << qs.out;
}

// ------------------------------------------------------------------------------------------------------------
// A user's input mistakes that check names (issue 44).

// The small bent vessel typed in millimetres (a vessel of 1.5 m radius) builds and checks as one a thousand
// times too large; check names its radius and its centre-line with the fix among its warnings (it said
// nothing). In metres: no such warning.
TEST(CheckCommand, AVesselTypedInMillimetresIsNamedWithTheFix) {
  const std::string tiny = test::source_path("tests/data/tiny-bent-vessel.json");
  const CliResult mm = cli(with_sets(
      {"-q", "check", tiny},
      {"geometry.outer_radius_m=1.5", "geometry.wall_thickness_m=0.4", "geometry.node_spacing_m=0.4",
       "geometry.centerline.radius_of_curvature_m=5", "geometry.centerline.leg_length_m=1",
       "regions.2.select.s_half_length_m=0.5", "regions.2.bc.magnitude_m=0.2", "output.surface=false"}));
  ASSERT_EQ(mm.code, 0) << mm.err;
  EXPECT_TRUE(
      mm.out_has("  warning   " + tiny +
                 ": key 'geometry.outer_radius_m': a vessel radius of 1.5 m is "
                 "implausible (above 0.05 m); if these are millimetres, write them in metres (1.5e-3)"))
      << mm.out;
  EXPECT_TRUE(
      mm.out_has("key 'geometry.centerline.radius_of_curvature_m': a centre-line length of 9.854 m is "
                 "implausible (above 1 m); if these are millimetres, write them in metres (5e-3)"))
      << mm.out;
  const CliResult metres = cli({"-q", "check", tiny, "--set", "output.surface=false"});
  ASSERT_EQ(metres.code, 0) << metres.err;
  EXPECT_FALSE(metres.out_has("implausible")) << metres.out;
}

// The small vessel's 0.4 mm wall at coarser spacings: at 2x it builds, and check warns naming the spacing; at
// 4x the surface map's guard fails (exit 3), and its message names the spacing before the growths that would
// make it run (it named only the growths); the support guard, failed at 1.5x, does the same. A guard failing
// on the scene's own lattice (1x) names only the growths.
TEST(CheckCommand, ALatticeCoarseForItsWallIsNamedBeforeTheGrowths) {
  const std::string tiny = test::source_path("tests/data/tiny-bent-vessel.json");
  const CliResult twice =
      cli({"-q", "check", tiny, "--set", "geometry.node_spacing_m=0.8e-3", "--set", "output.surface=false"});
  ASSERT_EQ(twice.code, 0) << twice.err;
  EXPECT_TRUE(twice.out_has("  warning   " + tiny +
                            ": key 'geometry.node_spacing_m': the node spacing along the wall, "
                            "0.0008 m, is 2x the wall thickness (0.0004 m)"))
      << twice.out;
  EXPECT_TRUE(twice.out_has("reduce geometry.node_spacing_m to at most 0.0004 m")) << twice.out;
  const CliResult map = cli({"-q", "check", tiny, "--set", "geometry.node_spacing_m=1.6e-3", "--set",
                             "regions.2.select.s_half_length_m=3e-3"});
  ASSERT_EQ(map.code, 3) << map.err;
  ASSERT_EQ(map.messages.size(), 1u) << map.err;
  EXPECT_NE(map.messages[0].find(
                "vertices fail): reduce geometry.node_spacing_m (now 4x the wall thickness; forces are "
                "measured accurate up to 1x); or let the support grow further: mapping.max_growths = "),
            std::string::npos)
      << map.messages[0];
  const CliResult support =
      cli({"-q", "check", tiny, "--set", "geometry.node_spacing_m=0.6e-3", "--set",
           "discretization.max_growths=0", "--set", "discretization.support_radius_factor=1.01"});
  ASSERT_EQ(support.code, 3) << support.err;
  EXPECT_TRUE(support.err_has(
      "nodes fail): reduce geometry.node_spacing_m (now 1.5x the wall thickness; forces are "
      "measured accurate up to 1x); or let the support grow further: discretization.max_growths "
      "= "))
      << support.err;
  const CliResult own = cli(
      {"-q", "check", tiny, "--set", "mapping.max_growths=0", "--set", "mapping.support_radius_factor=1.5"});
  ASSERT_EQ(own.code, 3) << own.err;
  EXPECT_FALSE(own.err_has("reduce geometry.node_spacing_m")) << own.err;
  EXPECT_TRUE(own.err_has("vertices fail): let the support grow further: mapping.max_growths = ")) << own.err;
}

// A catheter that keeps the nodes off itself (node_radius_m) in a scene that leaves contact.surface to its
// default (tiny-catheter's contact block emptied): check names the obstacle, the key and what it changes. The
// scene as bundled chooses the nodes' contact and is not warned.
TEST(CheckCommand, ANodeRadiusThatMovesTheContactToTheNodesIsNamed) {
  const std::string tiny = test::source_path("tests/data/tiny-catheter.json");
  const CliResult by_default =
      cli({"-q", "check", tiny, "--set", "contact={}", "--set", "output.surface=false"});
  ASSERT_EQ(by_default.code, 0) << by_default.err;
  EXPECT_TRUE(
      by_default.out_has("  warning   " + tiny +
                         ": key 'obstacles.0.node_radius_m': obstacle 'catheter' keeps "
                         "the nodes 0.0001 m off the tool, which moves the contact of every tool from the "
                         "wall's surface"))
      << by_default.out;
  const CliResult chosen = cli({"-q", "check", tiny, "--set", "output.surface=false"});
  ASSERT_EQ(chosen.code, 0) << chosen.err;
  EXPECT_FALSE(chosen.out_has("node_radius_m")) << chosen.out;
}

// The contact-resolution warning of a run is printed once per tool (it was logged and printed again at the
// end), and what it names from the spacing on is the lattice's and the tool's: the same with 3 load steps and
// with 6.
TEST(RunWarnings, TheContactResolutionWarningIsPrintedOncePerToolWhateverTheLoadSteps) {
  const fs::path dir = test_dir();
  const std::string tiny = test::source_path("tests/data/tiny-catheter.json");
  const std::string head = "the contact of the tool 'catheter' was narrower than the lattice resolves";
  std::vector<std::string> tails;
  for (const std::string steps : {"3", "6"}) {
    const CliResult r = cli({"run", tiny, "--out", (dir / steps).string(), "--set",
                             "quasi_static.load_steps=" + steps, "--set", "output.surface=false"});
    ASSERT_EQ(r.code, 0) << r.out << r.err;
    const std::string printed = r.out + r.err;
    std::size_t count = 0;
    for (std::size_t at = printed.find(head); at != std::string::npos; at = printed.find(head, at + 1))
      ++count;
    EXPECT_EQ(count, 1u) << printed;
    const nlohmann::json summary = read_json(dir / steps / "summary.json");
    for (const auto& w : summary["warnings"]) {
      const std::string text = w.get<std::string>();
      if (text.find(head) != std::string::npos)
        tails.push_back(text.substr(text.find("of the lattice's node spacings")));
    }
  }
  ASSERT_EQ(tails.size(), 2u);
  EXPECT_EQ(tails[0], tails[1]);
}

}  // namespace
}  // namespace vascsim
