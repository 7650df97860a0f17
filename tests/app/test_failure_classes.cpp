// The failure classes found by hostile input (docs/reliability.md), each from its reproducer on a tiny scene:
// bad input is one line naming the file and the key with exit code 2, never a crash, a hang, exit 1 or a
// silent result; a run that cannot write its files fails with exit 2 naming the file; Ctrl-C stops at a step
// boundary with exit 130 and complete files. In-process through run_cli; about a second in all.

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "support/cli_capture.hpp"
#include "support/scenes.hpp"
#include "vascsim/core/interrupt.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace vascsim::test;

const std::string kData = std::string(VASCSIM_SOURCE_DIR) + "/tests/data/";

std::string box_scene(const fs::path& dir, const json& changes = json::object()) {
  json scene = tiny_box();
  scene.merge_patch(changes);
  return write_file(dir / "box.json", scene.dump(2));
}

/// Exit 2 and exactly one message line holding every one of `parts` (file, key, ...).
void expect_input_error(const CliCapture& r, const std::vector<std::string>& parts) {
  EXPECT_EQ(r.code, 2) << r.err;
  ASSERT_EQ(r.messages.size(), 1u) << r.err;
  for (const auto& p : parts)
    EXPECT_NE(r.messages[0].find(p), std::string::npos) << "'" << p << "' in " << r.messages[0];
}

// ---------------------------------------------------------------------------------------------------------------
// Crashes

TEST(FailureClasses, SceneNestedTwoHundredThousandLevelsIsAnInputError) {
  const fs::path dir = fresh_test_dir();
  const std::string deep = std::string(200000, '[') + std::string(200000, ']');
  const std::string file = write_file(dir / "deep.json", R"({"name": "deep", "description": )" + deep + "}");
  expect_input_error(run_cli_captured({"run", file, "--out", (dir / "out").string()}),
                     {file, "nest deeper than 64"});
  // The same depth as a --set value: not JSON within the limit, so a bare word, and a string is no number.
  const std::string box = box_scene(dir);
  expect_input_error(run_cli_captured({"run", box, "--set", "material.youngs_modulus_pa=" + deep}),
                     {box, "material.youngs_modulus_pa", "expected a number"});
}

// Regions that hold every node leave nothing to solve: the run used to exit 3 ("sparse Cholesky: analysis of
// a 0 x 0 matrix failed"), for every model.
TEST(FailureClasses, RegionsThatHoldEveryNodeAreAnInputError) {
  const fs::path dir = fresh_test_dir();
  const json all = json::parse(R"([{ "name": "all", "select": { "type": "box", "max_m": [1, 1, 1] },
                                     "bc": { "type": "fixed" } }])");
  const std::string box = box_scene(dir, {{"regions", all}});
  for (const std::string model : {"quasi_static", "implicit", "xpbd"})
    expect_input_error(
        run_cli_captured({"run", box, "--set", "model=" + model, "--out", (dir / model).string()}),
        {box, "'regions'", "hold all 125 nodes", "('all')"});
}

TEST(FailureClasses, VtkFrameThatCannotBeWrittenIsAnInputErrorNotAnAbort) {
  const fs::path dir = fresh_test_dir(), out = dir / "out";
  const std::string box = box_scene(dir, {{"output", {{"vtk", true}}}});
  fs::create_directories(out / "vtk");
  // Frames go through "<name>.tmp" and a rename; a temporary file on a full disk fails the run (exit 2).
  fs::create_symlink("/dev/full", out / "vtk" / "nodes_0001.vtu.tmp");
  expect_input_error(run_cli_captured({"run", box, "--out", out.string()}),
                     {"nodes_0001.vtu", "cannot write"});
  // The issue's reproducer, the frame itself a link to /dev/full: the rename replaces the link with the
  // frame.
  fs::remove_all(out);
  fs::create_directories(out / "vtk");
  fs::create_symlink("/dev/full", out / "vtk" / "nodes_0001.vtu");
  const CliCapture r = run_cli_captured({"run", box, "--out", out.string()});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(fs::is_symlink(out / "vtk" / "nodes_0001.vtu"));
  const std::string frame = read_file(out / "vtk" / "nodes_0001.vtu");
  EXPECT_NE(frame.rfind("</VTKFile>\n"), std::string::npos) << "the frame is complete";
}

// ---------------------------------------------------------------------------------------------------------------
// Hangs and overflowing counts

TEST(FailureClasses, ExplicitStepTooSmallIsAnInputErrorAtItsKey) {
  const fs::path dir = fresh_test_dir();
  const std::string box = box_scene(dir, {{"model", "explicit"}});
  for (const char* dt : {"1e-300", "1e-15"})
    expect_input_error(run_cli_captured({"run", box, "--set", std::string("explicit.dt_s=") + dt}),
                       {box, "explicit.dt_s", "the limit is"});
}

TEST(FailureClasses, OutputCountOverflowIsAnInputErrorForEveryDynamicModel) {
  const fs::path dir = fresh_test_dir();
  const std::string box = box_scene(dir);
  for (const std::string model : {"explicit", "xpbd", "paper_literal", "implicit", "mass_spring"})
    expect_input_error(
        run_cli_captured({"run", box, "--set", "model=" + model, "--set", model + ".duration_s=1e4", "--set",
                          model + ".output_interval_s=1e-9"}),
        {box, model + ".output_interval_s", "output points"});
}

TEST(FailureClasses, ReplayFromADeviceFileReturnsAtOnce) {
  const CliCapture r = run_cli_captured({"run", kData + "haptic-block.json", "--replay", "/dev/zero"});
  expect_input_error(r, {"/dev/zero", "not a regular file"});
}

// ---------------------------------------------------------------------------------------------------------------
// Silent wrong results

TEST(FailureClasses, TrajectoryLongerThanTheTickLimitIsAnInputError) {
  const fs::path dir = fresh_test_dir();
  for (const char* end : {"1e300", "3e5"}) {
    const std::string trajectory =
        write_file(dir / "long.csv",
                   std::string("time_s,x_m,y_m,z_m\n0,0.003,0.003,0.0032\n") + end + ",0.003,0.003,0.0032\n");
    json scene = json::parse(read_file(kData + "haptic-block.json"));
    scene["haptics"]["device"]["trajectory"] = trajectory;
    const std::string file = write_file(dir / "long.json", scene.dump());
    expect_input_error(run_cli_captured({"run", file, "--out", (dir / "out").string()}),
                       {trajectory, "ticks", "at most 2e+07"});
  }
}

TEST(FailureClasses, DisplacementLargerThanTheBodyIsAnInputError) {
  const fs::path dir = fresh_test_dir();
  json push = tiny_box()["regions"];
  push[1]["bc"]["magnitude_m"] = 10.0;
  const std::string box = box_scene(dir, {{"regions", push}});
  expect_input_error(run_cli_captured({"run", box, "--out", (dir / "out").string()}),
                     {box, "regions.1.bc.magnitude_m", "larger than the body"});
}

TEST(FailureClasses, ProbesCsvOnAFullDiskFailsTheRun) {
  const fs::path dir = fresh_test_dir(), out = dir / "out";
  fs::create_directories(out);
  fs::create_symlink("/dev/full", out / "probes.csv");
  expect_input_error(run_cli_captured({"run", box_scene(dir), "--out", out.string()}),
                     {"probes.csv", "cannot write"});
}

// ---------------------------------------------------------------------------------------------------------------
// Internal errors

TEST(FailureClasses, SceneThatIsAFolderIsAnInputError) {
  const fs::path dir = fresh_test_dir();
  expect_input_error(run_cli_captured({"run", dir.string()}), {dir.string(), "is a folder"});
}

TEST(FailureClasses, TextThatIsNotUtf8IsAnInputErrorOrWrittenReplaced) {
  const fs::path dir = fresh_test_dir();
  const std::string box = box_scene(dir);
  expect_input_error(run_cli_captured({"run", box, "--set", "description=caf\xE9"}),
                     {"--set", "description", "not valid UTF-8"});
  // A scene path in another encoding: the run completes and summary.json is valid JSON.
  const fs::path latin1 = dir / "sc\xE8ne.json";
  fs::copy_file(box, latin1);
  const CliCapture r = run_cli_captured({"run", latin1.string(), "--out", (dir / "out").string()});
  ASSERT_EQ(r.code, 0) << r.err;
  const json summary = json::parse(read_file(dir / "out" / "summary.json"));
  EXPECT_NE(summary["scene_file"].get<std::string>().find("\xEF\xBF\xBD"), std::string::npos)
      << "the byte that is not UTF-8 is written as U+FFFD";
}

// ---------------------------------------------------------------------------------------------------------------
// Unclear messages

TEST(FailureClasses, NegativePoissonRatioNamesItsKey) {
  const fs::path dir = fresh_test_dir();
  const std::string box = box_scene(dir);
  expect_input_error(run_cli_captured({"run", box, "--set", "material.poisson_ratio=-0.3"}),
                     {box, "material.poisson_ratio", "allowed [0, 0.499]"});
}

TEST(FailureClasses, HapticLimitsNameTheFileAndKey) {
  const std::string scene = kData + "haptic-block.json";
  expect_input_error(run_cli_captured({"run", scene, "--set", "haptics.force_limit_n=0"}),
                     {scene, "haptics.force_limit_n"});
  // One tick a second: the virtual coupling is unstable at that tick; the message names the scene's keys.
  expect_input_error(run_cli_captured({"run", scene, "--set", "haptics.rate_hz=1", "--set", "xpbd.step_s=1",
                                       "--set", "xpbd.output_interval_s=1", "--set", "xpbd.duration_s=2"}),
                     {scene, "haptics", "rate_hz = 1 Hz"});
}

TEST(FailureClasses, JsonSyntaxErrorsAreOursOnOneLine) {
  const fs::path dir = fresh_test_dir();
  const std::string file = write_file(dir / "broken.json", "{\n  \"name\": \n}\n");
  const CliCapture r = run_cli_captured({"run", file});
  expect_input_error(r, {file, "not valid JSON: line 3, column 1"});
  EXPECT_EQ(r.err.find("json.exception"), std::string::npos) << r.err;
  // A string with a newline in it stays on the one line, escaped.
  expect_input_error(run_cli_captured({"run", box_scene(dir), "--set", R"(name="two\nlines")"}),
                     {"two\\nlines"});
}

TEST(FailureClasses, XpbdOutputIntervalShorterThanTheStepWarns) {
  const fs::path dir = fresh_test_dir();
  const CliCapture r =
      run_cli_captured({"run", box_scene(dir), "--out", (dir / "out").string(), "--set", "model=xpbd",
                        "--set", "xpbd.step_s=1e-3", "--set", "xpbd.output_interval_s=5e-4", "--set",
                        "xpbd.duration_s=1e-3", "--set", "xpbd.ramp_time_s=0"});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("[warning] key 'xpbd.step_s': output_interval_s = 0.0005 s is shorter than the step"),
            std::string::npos)
      << r.err;
}

TEST(FailureClasses, EmptyOutputPathsAreRejected) {
  const fs::path dir = fresh_test_dir();
  for (const char* option : {"--out", "--record"}) {
    const CliCapture r = run_cli_captured({"run", kData + "haptic-block.json", option, ""});
    EXPECT_EQ(r.code, 2) << r.err;
    ASSERT_EQ(r.messages.size(), 1u) << r.err;
    EXPECT_NE(r.messages[0].find(option), std::string::npos) << r.messages[0];
  }
}

// ---------------------------------------------------------------------------------------------------------------
// Interrupts

TEST(FailureClasses, InterruptedRunExits130WithCompleteFiles) {
  const fs::path dir = fresh_test_dir(), out = dir / "out";
  vascsim::request_interrupt();  // as the SIGINT handler does; the run stops at its first step boundary
  const CliCapture r =
      run_cli_captured({"run", box_scene(dir, {{"output", {{"vtk", true}}}}), "--out", out.string()});
  EXPECT_FALSE(vascsim::interrupt_requested()) << "run_cli lowers the flag after reporting it";
  vascsim::clear_interrupt();
  EXPECT_EQ(r.code, vascsim::kInterruptedExitCode) << r.err;
  EXPECT_NE(r.err.find("interrupted"), std::string::npos) << r.err;
  const json summary = json::parse(read_file(out / "summary.json"));
  EXPECT_TRUE(summary["interrupted"].get<bool>());
  EXPECT_EQ(summary["steps"].size(), 1u) << "the rest state only";
  EXPECT_EQ(summary["planned_steps"].get<int>(), 2);
  EXPECT_NE(read_file(out / "vtk" / "nodes.pvd").find("nodes_0000.vtu"), std::string::npos);
}

}  // namespace
