// Scene files and the `vascsim run` command (docs/scene-format.md): every class of bad input exits
// with code 2 and one message line that names the file and the key; overrides (--set) are checked like
// keys in the file; a tiny scene runs and writes summary.json, probes.csv (and the VTK series) as
// documented. Everything here runs in-process through vascsim::run_cli and takes about a second.

#include <gtest/gtest.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "support/cli_capture.hpp"
#include "support/scene_errors.hpp"
#include "support/scenes.hpp"
#include "vascsim/app/cli.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/model/explicit_model.hpp"
#include "vascsim/model/quasi_static_model.hpp"
#include "vascsim/scene/scene.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace vascsim;
using vascsim::test::tiny_box;

// ---------------------------------------------------------------------------------------------
// Helpers

using CliResult = vascsim::test::CliCapture;

CliResult cli(const std::vector<std::string>& args) {
  return vascsim::test::run_cli_captured(args);
}

/// This process's scratch folder under testing::TempDir().
fs::path scratch_root() {
  return fs::path(::testing::TempDir()) / ("vascsim_scene_" + std::to_string(::getpid()));
}

/// Removes the scratch folder after the run, unless a test failed (its files help to debug it).
class ScratchCleanup : public ::testing::Environment {
 public:
  void TearDown() override {
    std::error_code ec;
    if (::testing::UnitTest::GetInstance()->Passed()) fs::remove_all(scratch_root(), ec);
  }
};
[[maybe_unused]] ::testing::Environment* const scratch_cleanup =
    ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

/// A fresh, empty folder for the current test.
fs::path test_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path d = scratch_root() / (std::string(info->test_suite_name()) + "." + info->name());
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string write_text(const fs::path& file, const std::string& text) {
  std::ofstream(file) << text;
  return file.string();
}

std::string write_scene(const fs::path& file, const json& scene) {
  return write_text(file, scene.dump(2));
}

std::string read_text(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A valid tube (3 layers x 20 around x 5 rings = 300 nodes): both end rings clamped, a 3 x 3 node
/// patch on the outer wall at theta = 90 deg pushed 50 um inward.
json tiny_tube() {
  return json::parse(R"({
    "name": "tiny-tube",
    "geometry": { "type": "tube", "outer_radius_m": 1.5e-3, "wall_thickness_m": 0.4e-3, "length_m": 1.6e-3,
                  "node_spacing_m": 0.4e-3 },
    "regions": [
      { "name": "end_start", "select": { "type": "cylinder_end", "end": "start" },
        "bc": { "type": "fixed" } },
      { "name": "end_finish", "select": { "type": "cylinder_end", "end": "end" },
        "bc": { "type": "fixed" } },
      { "name": "indenter",
        "select": { "type": "wall_patch", "surface": "outer", "angle_center_deg": 90,
                    "angle_half_width_deg": 20, "z_center_m": 0.8e-3, "z_half_length_m": 0.4e-3 },
        "bc": { "type": "displacement", "direction": "inward", "magnitude_m": 5e-5 } },
      { "name": "wall", "select": { "type": "all" } }
    ],
    "probes": [ { "name": "apex", "position_m": [0, 1.5e-3, 0.8e-3], "component": "y" } ],
    "quasi_static": { "load_steps": 3, "rel_tolerance": 1e-6 },
    "output": { "vtk": false, "vtk_every": 2 }
  })");
}

/// Runs `vascsim -q run SCENE --out DIR/out [extra]` and checks exit code 2 with exactly one message
/// line, prefixed "vascsim: error: " and containing every fragment.
void expect_input_error(const std::string& scene_path, const std::vector<std::string>& extra,
                        const std::vector<std::string>& fragments) {
  std::vector<std::string> args = {"-q", "run", scene_path, "--out",
                                   (fs::path(scene_path).parent_path() / "out").string()};
  args.insert(args.end(), extra.begin(), extra.end());
  const CliResult r = cli(args);
  SCOPED_TRACE("stderr:\n" + r.err);
  EXPECT_EQ(r.code, 2);
  ASSERT_EQ(r.messages.size(), 1u) << "expected one message line";
  EXPECT_EQ(r.messages[0].rfind("vascsim: error: ", 0), 0u) << r.messages[0];
  for (const auto& f : fragments)
    EXPECT_NE(r.messages[0].find(f), std::string::npos) << "missing '" << f << "'";
}

/// Writes `scene` to DIR/name.json and expects an input error naming that file and `key` (as
/// "key '<key>'") plus the other fragments.
void expect_scene_error(const json& scene, const std::string& key, const std::vector<std::string>& more = {},
                        const std::vector<std::string>& extra_args = {}, const std::string& name = "scene") {
  const std::string path = write_scene(test_dir() / (name + ".json"), scene);
  std::vector<std::string> fragments = {path + ": ", "key '" + key + "'"};
  fragments.insert(fragments.end(), more.begin(), more.end());
  expect_input_error(path, extra_args, fragments);
}

std::vector<std::string> split(const std::string& line, char sep = ',') {
  std::vector<std::string> out;
  std::stringstream s(line);
  for (std::string cell; std::getline(s, cell, sep);) out.push_back(cell);
  if (!line.empty() && line.back() == sep) out.emplace_back();
  return out;
}

double parse_number(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  EXPECT_TRUE(!text.empty() && end == text.c_str() + text.size()) << "not a number: '" << text << "'";
  return v;
}

// ---------------------------------------------------------------------------------------------
// Bad input: exit code 2, one line naming the file and the key

TEST(SceneValidation, UnknownTopLevelKey) {
  json s = tiny_box();
  s["load_step"] = 3;
  expect_scene_error(s, "load_step", {"unknown key", "allowed here:", "quasi_static"});
}

TEST(SceneValidation, UnknownNestedKey) {
  json s = tiny_box();
  s["material"]["youngs_modulus"] = 1e6;
  expect_scene_error(s, "material.youngs_modulus", {"unknown key", "youngs_modulus_pa"});
}

TEST(SceneValidation, UnknownKeyInsideArrayElement) {
  json s = tiny_box();
  s["regions"][1]["bc"]["magnitude"] = 1e-5;
  expect_scene_error(s, "regions.1.bc.magnitude", {"unknown key"});
}

TEST(SceneValidation, WrongType) {
  {
    json s = tiny_box();
    s["material"]["poisson_ratio"] = "0.3";
    expect_scene_error(s, "material.poisson_ratio", {"expected a number", "found a string"});
  }
  {
    json s = tiny_box();
    s["output"] = {{"vtk", 1}};
    expect_scene_error(s, "output.vtk", {"expected true or false", "found a number"});
  }
  {
    json s = tiny_box();
    s["geometry"]["min_m"] = {0, 0};
    expect_scene_error(s, "geometry.min_m", {"array of 3 numbers"});
  }
  {
    json s = tiny_box();
    s["regions"] = json::object();
    expect_scene_error(s, "regions", {"expected an array of objects", "found an object"});
  }
  {
    json s = tiny_box();
    s["quasi_static"]["load_steps"] = 2.5;
    expect_scene_error(s, "quasi_static.load_steps", {"expected an integer"});
  }
}

TEST(SceneValidation, ValueOutOfRange) {
  {
    json s = tiny_box();
    s["material"]["poisson_ratio"] = 0.5;
    expect_scene_error(s, "material.poisson_ratio", {"out of range", "0.499"});
  }
  {
    json s = tiny_box();
    s["geometry"]["node_spacing_m"] = -2.5e-4;
    expect_scene_error(s, "geometry.node_spacing_m", {"out of range"});
  }
  {
    json s = tiny_box();
    s["quasi_static"]["load_steps"] = 0;
    expect_scene_error(s, "quasi_static.load_steps", {"out of range"});
  }
}

TEST(SceneValidation, MissingRequiredKey) {
  {
    json s = tiny_box();
    s["geometry"].erase("type");
    expect_scene_error(s, "geometry.type", {"missing", "tube, vessel, mesh, box, beam"});
  }
  {
    json s = tiny_box();
    s["geometry"].erase("node_spacing_m");
    expect_scene_error(s, "geometry.node_spacing_m", {"missing"});
  }
  {
    json s = tiny_box();
    s["regions"][1]["bc"].erase("magnitude_m");
    expect_scene_error(s, "regions.1.bc.magnitude_m", {"missing"});
  }
}

TEST(SceneValidation, UnknownEnumValue) {
  {
    json s = tiny_box();
    s["model"] = "implicit_euler";
    expect_scene_error(s, "model", {"unknown value 'implicit_euler'", "quasi_static, explicit"});
  }
  {
    json s = tiny_box();
    s["regions"][0]["bc"]["type"] = "clamped";
    expect_scene_error(s, "regions.0.bc.type",
                       {"unknown value 'clamped'", "fixed, displacement, force, probe"});
  }
  {
    json s = tiny_box();
    s["formulation"] = "literal";
    expect_scene_error(s, "formulation", {"unknown value 'literal'", "sound, paper_literal"});
  }
}

TEST(SceneValidation, DirectionErrors) {
  {
    json s = tiny_box();  // "inward" needs a wall_patch selector
    s["regions"][1]["bc"]["direction"] = "inward";
    expect_scene_error(s, "regions.1.bc.direction", {"wall_patch"});
  }
  {
    json s = tiny_box();
    s["regions"][1]["bc"]["direction"] = {0, 0, 0};
    expect_scene_error(s, "regions.1.bc.direction", {"zero vector"});
  }
  {
    json s = tiny_box();  // vector and direction + magnitude together
    s["regions"][1]["bc"]["vector_m"] = {0, 0, -1e-5};
    expect_scene_error(s, "regions.1.bc.vector_m", {"not both"});
  }
}

TEST(SceneValidation, RootMustBeAnObject) {
  const fs::path dir = test_dir();
  const std::string path = write_text(dir / "array.json", "[1, 2, 3]");
  expect_input_error(path, {}, {path + ": ", "key '(root)'", "expected an object"});
}

TEST(SceneValidation, MissingSceneFile) {
  const std::string path = (test_dir() / "no-such-scene.json").string();
  expect_input_error(path, {}, {path + ": ", "cannot open"});
}

TEST(SceneValidation, InvalidJson) {
  const fs::path dir = test_dir();
  const std::string path =
      write_text(dir / "broken.json", "{ \"model\": \"quasi_static\",\n  \"geometry\": { \n");
  expect_input_error(path, {}, {path + ": ", "not valid JSON"});
  // A number beyond a double is an out_of_range in the JSON library, not a parse error: still exit 2.
  const std::string huge = write_text(dir / "huge.json", "{ \"gravity_m_s2\": [0, 0, 1e999] }");
  expect_input_error(huge, {}, {huge + ": ", "not valid JSON"});
}

TEST(SceneValidation, CommentsAreAllowed) {
  const fs::path dir = test_dir();
  const std::string path = write_text(dir / "commented.json", "// a comment\n" + tiny_box().dump(2));
  EXPECT_NO_THROW(load_scene(path));
}

TEST(SceneValidation, BadSetSyntax) {
  const std::string path = write_scene(test_dir() / "scene.json", tiny_box());
  // Each malformed override names itself (the override is not part of the file).
  for (const std::string bad : {"model", "=quasi_static", "material..poisson_ratio=0.3", "regions.x.name=a",
                                "regions.7.name=a", "name.first=a"}) {
    SCOPED_TRACE(bad);
    expect_input_error(path, {"--set", bad}, {"--set '" + bad + "'"});
  }
}

TEST(SceneValidation, SetOfUnknownKey) {
  const std::string path = write_scene(test_dir() / "scene.json", tiny_box());
  expect_input_error(path, {"--set", "material.youngs_modulus=1e6"},
                     {path + ": ", "key 'material.youngs_modulus'", "unknown key"});
  expect_input_error(path, {"--set", "regions.1.bc.magnitude=1"},
                     {path + ": ", "key 'regions.1.bc.magnitude'"});
}

TEST(SceneValidation, SetIsValidatedLikeTheFile) {
  const std::string path = write_scene(test_dir() / "scene.json", tiny_box());
  // A bare word is a string, so a mistyped number is a type error on the key it sets.
  expect_input_error(path, {"--set", "material.poisson_ratio=0.4x"},
                     {path + ": ", "key 'material.poisson_ratio'", "found a string"});
  expect_input_error(path, {"--set", "material.poisson_ratio=0.5"},
                     {path + ": ", "key 'material.poisson_ratio'", "out of range"});
  expect_input_error(path, {"--set", "model=implicit_euler"}, {path + ": ", "key 'model'", "unknown value"});
}

TEST(SceneValidation, DuplicateRegionName) {
  json s = tiny_box();
  s["regions"][1]["name"] = "base";
  expect_scene_error(s, "regions.1.name", {"duplicate region name 'base'"});
}

TEST(SceneValidation, InvalidRegionName) {
  json s = tiny_box();
  s["regions"][1]["name"] = "top face";
  expect_scene_error(s, "regions.1.name", {"'top face' is not allowed"});
}

TEST(SceneValidation, RegionSelectingNoNodes) {
  json s = tiny_box();
  s["regions"].push_back(json::parse(
      R"({ "name": "nowhere", "select": { "type": "box", "min_m": [1, 1, 1], "max_m": [2, 2, 2] } })"));
  const std::string path = write_scene(test_dir() / "scene.json", s);
  // Found after the geometry is built; the message names the region and its select block.
  expect_input_error(path, {},
                     {path + ": ", "region 'nowhere'", "selects no nodes", "key 'regions.2.select'"});
}

TEST(SceneValidation, TubeSelectorOnBox) {
  json s = tiny_box();
  s["regions"].push_back(
      json::parse(R"({ "name": "ring", "select": { "type": "cylinder_end", "end": "start" } })"));
  const std::string path = write_scene(test_dir() / "scene.json", s);
  expect_input_error(path, {}, {path + ": ", "region 'ring'", "needs a vessel geometry"});
}

TEST(SceneValidation, WallThicknessNotBelowOuterRadius) {
  for (const double t : {1.5e-3, 2e-3}) {
    json s = tiny_tube();
    s["geometry"]["wall_thickness_m"] = t;
    expect_scene_error(s, "geometry.wall_thickness_m", {"must be smaller than outer_radius_m"});
  }
}

// A misspelt required key is reported as the unknown key the file holds, with the key meant, in every block
// (it was reported as the key meant, missing: "key 'geometry.wall_thickness_m': missing"). A present key that
// is another allowed key is not taken for a misspelling (a capsule's b_m of its a_m, Mooney-Rivlin's c01_pa
// of its c10_pa: one edit apart each), and a key near nothing allowed gets no suggestion.
TEST(SceneValidation, AMisspeltRequiredKeyIsNamedAsTypedWithTheKeyMeant) {
  auto rename = [](json& block, const std::string& from, const std::string& to) {
    block[to] = block[from];
    block.erase(from);
  };
  {
    json s = tiny_tube();
    rename(s["geometry"], "wall_thickness_m", "wall_thicknes_m");
    expect_scene_error(
        s, "geometry.wall_thicknes_m",
        {"unknown key (did you mean 'wall_thickness_m'?); 'wall_thickness_m' is missing: a number in"});
  }
  {
    json s = tiny_tube();
    rename(s["regions"][2]["select"], "angle_half_width_deg", "angle_half_widht_deg");
    expect_scene_error(s, "regions.2.select.angle_half_widht_deg", {"did you mean 'angle_half_width_deg'?"});
  }
  {
    json s = tiny_tube();
    s["obstacles"] =
        json::parse(R"([{ "name": "probe", "radius_m": 1e-3, "center_m": [0, 2.6e-3, 0.8e-3] }])");
    expect_scene_error(s, "obstacles.0.center_m", {"did you mean 'centre_m'?"});
  }
  {
    json s = tiny_tube();
    s["obstacles"] =
        json::parse(R"([{ "name": "probe", "shape": "capsule", "radius_m": 1e-3, "b_m": [0, 3e-3, 1e-3] }])");
    expect_scene_error(s, "obstacles.0.a_m", {"missing; an array of 3 numbers"});
  }
  {
    json s = tiny_tube();
    s["material"] = {{"law", "mooney_rivlin"}, {"c01_pa", 1e4}, {"bulk_modulus_pa", 1e7}};
    expect_scene_error(s, "material.c10_pa", {"missing; a number in"});
  }
  {
    json s = tiny_tube();
    rename(s["regions"][2]["select"], "angle_half_width_deg", "spread");
    expect_scene_error(s, "regions.2.select.angle_half_width_deg", {"missing; a number in"});
  }
}

// An unknown key names the nearest allowed key where one is a few edits away; the list of allowed keys holds
// every key the block accepts, a vessel's refine included when the scene has no refine block (it was listed
// only with one).
TEST(SceneValidation, AnUnknownKeyNamesTheNearestAllowedKeyAndEveryAllowedKey) {
  {
    json s = tiny_tube();
    s["geometry"]["min_layer"] = 3;
    expect_scene_error(s, "geometry.min_layer", {"unknown key (did you mean 'min_layers'?); allowed here: "});
  }
  {
    json s = tiny_tube();
    s["quasi_static"]["load_step"] = 3;
    expect_scene_error(s, "quasi_static.load_step", {"did you mean 'load_steps'?"});
  }
  {
    json s = tiny_tube();
    s["load_step"] = 3;  // at the top level nothing is near it
    const std::string message = test::scene_error(s);
    EXPECT_EQ(message.find("did you mean"), std::string::npos) << message;
  }
  json s = tiny_tube();
  s["geometry"] = json::parse(R"({ "type": "vessel", "centerline": { "type": "straight", "length_m": 1.6e-3 },
                                   "outer_radius_m": 1.5e-3, "wall_thickness_m": 0.4e-3, "node_spacing_m": 0.4e-3,
                                   "bogus": 1 })");
  expect_scene_error(s, "geometry.bogus",
                     {"allowed here: centerline, fit_lattice_to_patch, lattice_angle_deg, min_layers, "
                      "node_spacing_m, outer_radius_m, refine, type, wall_thickness_m"});
}

// A misspelt key whose default breaks something else is named first, as typed and with the key meant, in
// every block: the problem its default made follows it (it was reported alone, naming a key the file holds
// correctly or never held: "key 'obstacles.0.radius_m': missing", "key 'regions.2.bc.direction': unknown key;
// allowed here: type").
TEST(SceneValidation, AMisspeltKeyIsNamedBeforeWhatItsDefaultBreaks) {
  {  // a catheter's shape: the default sphere needs a radius
    json s = tiny_tube();
    s["obstacles"] = json::parse(R"([{ "name": "catheter", "shpe": "catheter", "tip_m": [0, 2.6e-3, 0.8e-3],
                                       "direction": [0, -1, 0], "push_m": 1e-4 }])");
    expect_scene_error(
        s, "obstacles.0.shpe",
        {"unknown key (did you mean 'shape'?); without 'shape': key 'obstacles.0.radius_m': missing; "
         "a number in"});
  }
  {  // a bc's type: the default probe takes no direction
    json s = tiny_tube();
    s["regions"][2]["bc"]["tye"] = s["regions"][2]["bc"]["type"];
    s["regions"][2]["bc"].erase("type");
    expect_scene_error(s, "regions.2.bc.tye", {"unknown key (did you mean 'type'?); allowed here: type"});
  }
  {  // the alternative to s_center_m
    json s = tiny_tube();
    s["regions"][2]["select"].erase("z_center_m");
    s["regions"][2]["select"]["s_center_fractoin"] = 0.5;
    expect_scene_error(s, "regions.2.select.s_center_fractoin",
                       {"unknown key (did you mean 's_center_fraction'?); without 's_center_fraction': key "
                        "'regions.2.select.s_center_m': missing; a number in"});
  }
  {  // the viewer's superior: the default +z is the anterior given
    json s = tiny_tube();
    s["viewer"] = json::parse(R"({ "supeior": [0, 1, 0], "anterior": [0, 0, 1] })");
    expect_scene_error(
        s, "viewer.supeior",
        {"unknown key (did you mean 'superior'?); without 'superior': key 'viewer.anterior': must be a "
         "non-zero vector not parallel to viewer.superior"});
  }
  {  // a block under another name: its required key is missing
    json s = tiny_tube();
    s["model"] = "implicit";
    s["haptics"] = json::parse(R"({ "devce": { "type": "scripted", "trajectory": "press.csv" } })");
    expect_scene_error(
        s, "haptics.devce",
        {"unknown key (did you mean 'device'?); without 'device': key 'haptics.device.trajectory': "
         "missing; a string is required"});
  }
  {  // the top level's regions, which the lattice is fitted to
    json s = tiny_tube();
    s["geometry"]["fit_lattice_to_patch"] = "strips";
    s["regons"] = s["regions"];
    s.erase("regions");
    s.erase("probes");
    expect_scene_error(
        s, "regons",
        {"unknown key (did you mean 'regions'?); without 'regions': key 'geometry.fit_lattice_to_patch': "
         "there is no wall_patch region to fit the lattice to"});
  }
  {  // an instrument's preset
    json s = tiny_tube();
    s["instrument"] =
        json::parse(R"({ "preet": "guidewire-035", "length_m": 0.05, "drive": [[0, 0.01, 0]] })");
    expect_scene_error(
        s, "instrument.preet",
        {"unknown key (did you mean 'preset'?); without 'preset': key 'instrument.outer_diameter_m': "
         "missing; a number in"});
  }
}

// A key a block accepts is not taken for a misspelling of another it lacks, and is listed among the keys
// allowed whether or not the scene has it: an instrument's inner_diameter_m beside a missing outer_diameter_m
// (it was reported as "unknown key (did you mean 'outer_diameter_m'?)"), the top level's instrument (it was
// neither suggested nor listed without an instrument block), and an instrument's preset (not listed without
// one).
TEST(SceneValidation, AKeyTheBlockAcceptsIsNeverTakenForAMisspelling) {
  json custom = json::parse(R"({ "inner_diameter_m": 2e-4, "youngs_modulus_pa": 6e10, "poisson_ratio": 0.3,
                                 "density_kg_m3": 6450, "length_m": 0.05, "drive": [[0, 0.01, 0]] })");
  {
    json s = tiny_tube();
    s["instrument"] = custom;
    expect_scene_error(s, "instrument.outer_diameter_m", {"missing; a number in"});
  }
  {
    json s = tiny_tube();
    s["instrment"] = custom;
    expect_scene_error(s, "instrment",
                       {"unknown key (did you mean 'instrument'?); allowed here: ", " instrument, "});
  }
  {
    json s = tiny_tube();
    s["instrument"] = custom;
    s["instrument"]["outer_diameter_m"] = 4e-4;
    s["instrument"]["bogus"] = 1;
    expect_scene_error(s, "instrument.bogus", {"allowed here: ", " preset, "});
  }
}

TEST(SceneValidation, ReferenceNeedsAForceRegion) {
  json s = tiny_box();
  s["geometry"] = {
      {"type", "beam"}, {"length_m", 4e-3}, {"width_m", 1e-3}, {"height_m", 1e-3}, {"node_spacing_m", 5e-4}};
  s["reference"] = {{"type", "timoshenko_cantilever"}, {"region", "top"}};
  expect_scene_error(s, "reference.region", {"no force region named 'top'"});
}

TEST(SceneValidation, CommandLineUsageErrors) {
  for (const auto& args :
       std::vector<std::vector<std::string>>{{"run"}, {"frobnicate"}, {"-q", "run", "x.json", "--bogus"}}) {
    const CliResult r = cli(args);
    SCOPED_TRACE(r.err);
    EXPECT_EQ(r.code, 2);
    ASSERT_EQ(r.messages.size(), 1u);
    EXPECT_EQ(r.messages[0].rfind("vascsim: ", 0), 0u);
  }
}

// Bad vessel meshes: one line naming the mesh file, exit code 2, never a crash. The mesh reader's
// own cases (formats, orientation, every defect) are in test_mesh_import.cpp; here the CLI path.
TEST(SceneValidation, BadMeshFilesExitTwoWithOneLineNamingTheFile) {
  const fs::path dir = test_dir();
  // A tetrahedron's faces in ASCII STL, with a placeholder for one coordinate.
  auto tet_stl = [](const std::string& x) {
    const std::string v[4] = {x + " 0 0", "1 0 0", "0 1 0", "0 0 1"};
    const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    std::string s = "solid t\n";
    for (const auto& t : f)
      s += "facet normal 0 0 0\nouter loop\nvertex " + v[t[0]] + "\nvertex " + v[t[1]] + "\nvertex " +
           v[t[2]] + "\nendloop\nendfacet\n";
    return s + "endsolid t\n";
  };
  const std::vector<std::pair<std::string, std::string>> files = {
      {"missing.stl", ""},  // not written
      {"empty.stl", "<empty>"},
      {"points.xyz", "0 0 0\n1 0 0\n"},
      {"nan.stl", tet_stl("nan")},
  };
  for (const auto& [name, text] : files) {
    SCOPED_TRACE(name);
    const fs::path mesh = dir / name;
    if (!text.empty()) write_text(mesh, text == "<empty>" ? "" : text);
    json s = tiny_box();
    s["geometry"] = {
        {"type", "mesh"}, {"file", mesh.string()}, {"wall_thickness_m", 0.1}, {"node_spacing_m", 0.05}};
    s["regions"] = json::array();
    const std::string path = write_scene(dir / ("scene-" + name + ".json"), s);
    const CliResult r = cli({"-q", "run", path, "--out", (dir / "out").string()});
    EXPECT_EQ(r.code, 2) << r.err;
    ASSERT_EQ(r.messages.size(), 1u) << r.err;
    EXPECT_NE(r.messages[0].find(mesh.string()), std::string::npos) << r.messages[0];
  }
}

// An OBJ vertex line that is not three finite numbers (io/obj_check.cpp): `check` exits 2 with one line
// naming the mesh file and its line. Before the check, a NaN vertex no face uses and "1,5" (read as 1) were
// meshed and the check passed (exit 0), and a NaN vertex a face uses was named as "vertex 1 ... (nan, nan,
// nan)", not where it is.
TEST(SceneValidation, BadObjVertexExitsTwoNamingTheLine) {
  const fs::path dir = test_dir();
  const std::string faces = "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  const std::vector<std::pair<std::string, std::string>> files = {
      {"unused-nan.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 0 nan 0\n" + faces},  // line 5
      {"used-nan.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 nan 1\n" + faces},             // line 4
      {"comma.obj", "v 0 0 0\nv 1 0 0\nv 0 1,5 0\nv 0 0 1\n" + faces},                // line 3
  };
  const std::string lines[] = {"line 5: vertex 5", "line 4: vertex 4", "line 3: vertex 3"};
  for (std::size_t i = 0; i < files.size(); ++i) {
    const auto& [name, text] = files[i];
    SCOPED_TRACE(name);
    const fs::path mesh = dir / name;
    write_text(mesh, text);
    json s = tiny_box();
    s["geometry"] = {
        {"type", "mesh"}, {"file", mesh.string()}, {"wall_thickness_m", 0.1}, {"node_spacing_m", 0.1}};
    s["regions"] = json::parse(R"([{"name": "base", "select": {"type": "box", "max_m": [2, 0.2, 2]},
                                    "bc": {"type": "fixed"}}])");
    const std::string path = write_scene(dir / ("scene-" + name + ".json"), s);
    const CliResult r = cli({"-q", "check", path});
    EXPECT_EQ(r.code, 2) << r.err;
    ASSERT_EQ(r.messages.size(), 1u) << r.err;
    EXPECT_NE(r.messages[0].find(mesh.string() + ": OBJ: " + lines[i]), std::string::npos) << r.messages[0];
  }
}

TEST(SceneValidation, MessagesAreSingleLineFromParseScene) {
  json s = tiny_box();
  s["energy"] = {{"volume_stiffness_pa", -1.0}};
  try {
    parse_scene(s, "in-memory.json");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos);
    EXPECT_EQ(what.rfind("in-memory.json: key 'energy.volume_stiffness_pa': ", 0), 0u) << what;
  }
}

// ---------------------------------------------------------------------------------------------
// Accepted input

TEST(SceneFiles, ShippedScenesLoad) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(VASCSIM_SOURCE_DIR) / "scenes")) {
    if (entry.path().extension() != ".json") continue;
    ++count;
    const std::string path = entry.path().string();
    SCOPED_TRACE(path);
    Scene sc;
    ASSERT_NO_THROW(sc = load_scene(path));
    EXPECT_EQ(sc.file, path);
    EXPECT_FALSE(sc.regions.empty());
  }
  EXPECT_GE(count, 5);  // cantilever, vein-indent and the paper's three vessels at least
}

TEST(SceneFiles, Defaults) {
  const Scene sc = parse_scene(tiny_box(), "dir/tiny.json");
  EXPECT_EQ(sc.name, "tiny-box");
  EXPECT_EQ(parse_scene(json::parse(R"({"geometry": {"type": "box", "min_m": [0,0,0], "max_m": [1,1,1],
                                        "node_spacing_m": 0.5}})"),
                        "dir/tiny.json")
                .name,
            "tiny");  // the file stem
  EXPECT_EQ(sc.model, "quasi_static");
  EXPECT_EQ(sc.geometry.box.cells, Eigen::Vector3i(4, 4, 4));
  EXPECT_DOUBLE_EQ(sc.material.density_kg_m3, 1060.0);
  EXPECT_DOUBLE_EQ(sc.discretization.support_radius_factor, 2.0);
  EXPECT_EQ(sc.discretization.min_neighbours, 12);
  EXPECT_DOUBLE_EQ(sc.settings<ExplicitSettings>("explicit").duration_s, 0.02);
  EXPECT_EQ(sc.settings<QuasiStaticSettings>("quasi_static").preconditioner, "meshless");
  EXPECT_FALSE(sc.output.vtk);
  EXPECT_EQ(sc.output.vtk_every, 1);
  ASSERT_EQ(sc.regions.size(), 2u);
  EXPECT_EQ(sc.regions[0].bc, RegionBcType::Fixed);
  EXPECT_EQ(sc.regions[1].bc, RegionBcType::Displacement);
  EXPECT_DOUBLE_EQ(sc.regions[1].magnitude, 1e-5);
  EXPECT_EQ(sc.regions[1].direction, Vec3(0, 0, -1));
}

TEST(SceneFiles, FormulationPresetChangesDefaultsOnly) {
  json s = tiny_box();
  const Scene sound = parse_scene(s, "s.json");
  EXPECT_EQ(sound.discretization.volume, VolumeRule::TetPartition);
  EXPECT_EQ(sound.energy.strain, StrainMeasure::GreenHalf);
  EXPECT_DOUBLE_EQ(sound.energy.stabilizer_alpha, 0.1);

  s["formulation"] = "paper_literal";
  const Scene literal = parse_scene(s, "s.json");
  EXPECT_EQ(literal.discretization.volume, VolumeRule::MuellerKernel);
  EXPECT_EQ(literal.energy.strain, StrainMeasure::MuellerNoHalf);
  EXPECT_DOUBLE_EQ(literal.energy.stabilizer_alpha, 0.0);

  s["energy"] = {{"strain", "green"}, {"stabilizer_alpha", 0.2}};  // explicit keys win over the preset
  const Scene mixed = parse_scene(s, "s.json");
  EXPECT_EQ(mixed.energy.strain, StrainMeasure::GreenHalf);
  EXPECT_DOUBLE_EQ(mixed.energy.stabilizer_alpha, 0.2);
  EXPECT_EQ(mixed.discretization.volume, VolumeRule::MuellerKernel);
}

// ---------------------------------------------------------------------------------------------
// Accepted with a warning (Scene::warnings): what runs but is probably not meant

bool scene_has_warning(const Scene& sc, const std::string& text) {
  return std::any_of(sc.warnings.begin(), sc.warnings.end(),
                     [&](const std::string& w) { return w.find(text) != std::string::npos; });
}

std::string scene_warning_lines(const Scene& sc) {
  std::string out;
  for (const std::string& w : sc.warnings) out += w + "\n";
  return out;
}

// The tiny tube typed in millimetres (a vessel of 1.5 m radius and 1.6 m long) parses, and names its radius
// and its length with the fix; in metres it warns of nothing. A bent vessel's centre-line names the key that
// sets its length, and that key's value in the fix.
TEST(SceneWarnings, AVesselTypedInMillimetresIsNamed) {
  json s = tiny_tube();
  EXPECT_TRUE(parse_scene(s, "tube.json").warnings.empty())
      << scene_warning_lines(parse_scene(s, "tube.json"));
  for (const char* key : {"outer_radius_m", "wall_thickness_m", "length_m", "node_spacing_m"})
    s["geometry"][key] = 1e3 * s["geometry"][key].get<double>();
  for (const char* key : {"z_center_m", "z_half_length_m"})
    s["regions"][2]["select"][key] = 1e3 * s["regions"][2]["select"][key].get<double>();
  s["probes"][0]["position_m"] = {0, 1.5, 0.8};
  const Scene mm = parse_scene(s, "tube.json");
  EXPECT_TRUE(
      scene_has_warning(mm,
                        "tube.json: key 'geometry.outer_radius_m': a vessel radius of 1.5 m is implausible "
                        "(above 0.05 m); if these are millimetres, write them in metres (1.5e-3)"))
      << scene_warning_lines(mm);
  EXPECT_TRUE(
      scene_has_warning(mm,
                        "key 'geometry.length_m': a vessel length of 1.6 m is implausible (above 1 m); if "
                        "these are millimetres, write them in metres (1.6e-3)"))
      << scene_warning_lines(mm);
  json bent = tiny_tube();
  bent["geometry"] = json::parse(R"({ "type": "vessel", "outer_radius_m": 1.5e-3, "wall_thickness_m": 0.4e-3,
      "node_spacing_m": 0.4e-3, "centerline": { "type": "bent", "radius_of_curvature_m": 5, "angle_deg": 90 } })");
  EXPECT_TRUE(scene_has_warning(parse_scene(bent, "bent.json"),
                                "key 'geometry.centerline.radius_of_curvature_m': a "
                                "centre-line length of 7.854 m is implausible (above 1 m); "
                                "if these are millimetres, write them in metres (5e-3)"))
      << scene_warning_lines(parse_scene(bent, "bent.json"));
}

// A node spacing along the wall coarser than the forces are measured accurate at (docs/validation.md,
// "Real-time resolutions"): with the quadratic fit (quasi_static's default on walls) above 1x the wall's
// thickness, with the linear fit above 1.5x; on a graded lattice the window's spacing counts. The same
// lattice's failed guards name the spacing first (coarse_spacing_advice).
TEST(SceneWarnings, ALatticeCoarseForItsWallIsNamed) {
  json s = tiny_tube();  // a 0.4 mm wall at 0.4 mm: 1x
  const Scene at_limit = parse_scene(s, "tube.json");
  EXPECT_TRUE(at_limit.warnings.empty()) << scene_warning_lines(at_limit);
  EXPECT_EQ(at_limit.discretization.coarse_spacing_advice, "");
  s["geometry"]["node_spacing_m"] = 0.8e-3;
  const Scene coarse = parse_scene(s, "tube.json");
  EXPECT_TRUE(
      scene_has_warning(coarse,
                        "tube.json: key 'geometry.node_spacing_m': the node spacing along the wall, "
                        "0.0008 m, is 2x the wall thickness (0.0004 m), coarser than the 1x up to which the "
                        "forces are measured accurate (with the quadratic fit"))
      << scene_warning_lines(coarse);
  EXPECT_TRUE(scene_has_warning(coarse, "reduce geometry.node_spacing_m to at most 0.0004 m"))
      << scene_warning_lines(coarse);
  const std::string advice =
      "reduce geometry.node_spacing_m (now 2x the wall thickness; forces are measured "
      "accurate up to 1x)";
  EXPECT_EQ(coarse.discretization.coarse_spacing_advice, advice);
  EXPECT_EQ(coarse.mapping.coarse_spacing_advice, advice);
  // The linear fit: 1.25x passes, 2x is named with its own limit.
  s["discretization"] = {{"basis", "linear"}};
  s["geometry"]["node_spacing_m"] = 0.5e-3;
  EXPECT_TRUE(parse_scene(s, "tube.json").warnings.empty())
      << scene_warning_lines(parse_scene(s, "tube.json"));
  s["geometry"]["node_spacing_m"] = 0.8e-3;
  EXPECT_TRUE(scene_has_warning(parse_scene(s, "tube.json"),
                                "coarser than the 1.5x up to which the forces are measured "
                                "accurate (with the linear fit"));
  // A graded vessel 4x away from its window: the window's spacing is what counts.
  json graded = tiny_tube();
  graded["regions"].erase(2);
  graded["geometry"] =
      json::parse(R"({ "type": "vessel", "centerline": { "type": "straight", "length_m": 8e-3 },
      "outer_radius_m": 1.5e-3, "wall_thickness_m": 0.3e-3, "node_spacing_m": 1.2e-3,
      "refine": { "angle_center_deg": 90, "angle_half_width_deg": 20, "s_half_length_m": 1e-3,
                  "node_spacing_m": 0.15e-3 } })");
  const Scene fine_window = parse_scene(graded, "graded.json");
  EXPECT_TRUE(fine_window.warnings.empty()) << scene_warning_lines(fine_window);
  EXPECT_NE(fine_window.discretization.coarse_spacing_advice, "");  // a failed guard would be away from it
  graded["geometry"]["refine"]["node_spacing_m"] = 0.45e-3;
  EXPECT_TRUE(scene_has_warning(parse_scene(graded, "graded.json"),
                                "key 'geometry.refine.node_spacing_m': the node "
                                "spacing along the wall, 0.00045 m, is 1.5x"));
}

// An obstacle's node_radius_m moves the contact from the wall's surface (the default with quasi_static's wall
// discretisation) to the nodes and presses the wall by that radius: named, unless the scene chose the nodes
// (contact.surface) or the model's default is the nodes anyway.
TEST(SceneWarnings, ANodeRadiusThatMovesTheContactToTheNodesIsNamed) {
  json s = tiny_tube();
  s["obstacles"] = json::parse(R"([{ "name": "probe", "radius_m": 1e-3, "centre_m": [0, 2.6e-3, 0.8e-3],
                                     "motion_m": [0, -1e-4, 0] }])");
  const Scene surface = parse_scene(s, "tube.json");
  EXPECT_TRUE(surface.contact.embedded);
  EXPECT_TRUE(surface.warnings.empty()) << scene_warning_lines(surface);
  s["obstacles"][0]["node_radius_m"] = 0.1e-3;
  const Scene nodes = parse_scene(s, "tube.json");
  EXPECT_FALSE(nodes.contact.embedded);
  EXPECT_TRUE(
      scene_has_warning(nodes,
                        "tube.json: key 'obstacles.0.node_radius_m': obstacle 'probe' keeps the nodes 0.0001 "
                        "m off the tool, which moves the contact of every tool from the wall's surface"))
      << scene_warning_lines(nodes);
  EXPECT_TRUE(scene_has_warning(nodes, "set contact.surface to \"nodes\" if the nodes' contact is meant"));
  s["contact"] = {{"surface", "nodes"}};
  EXPECT_TRUE(parse_scene(s, "tube.json").warnings.empty())
      << scene_warning_lines(parse_scene(s, "tube.json"));
  s.erase("contact");
  s["model"] = "implicit";  // its default contact is the nodes
  EXPECT_TRUE(parse_scene(s, "tube.json").warnings.empty())
      << scene_warning_lines(parse_scene(s, "tube.json"));
}

// The real-time scenes choose the surface contact; a model without it (a baseline switched in with --set) is
// told which models have it and how to keep the tools on the nodes.
TEST(SceneErrors, ASurfaceContactWithAModelWithoutItNamesTheFix) {
  json s = tiny_tube();
  s["obstacles"] = json::parse(R"([{ "name": "probe", "radius_m": 1e-3, "centre_m": [0, 2.6e-3, 0.8e-3],
                                     "motion_m": [0, -1e-4, 0] }])");
  s["contact"] = {{"surface", "embedded"}};
  s["model"] = "xpbd";
  expect_scene_error(s, "contact.surface",
                     {"supported by the models quasi_static, implicit", "model is 'xpbd'",
                      "set contact.surface to \"nodes\""});
  s["contact"]["surface"] = "nodes";
  EXPECT_FALSE(parse_scene(s, "tube.json").contact.embedded);
}

TEST(SceneOverride, SetModelExplicitChangesTheModel) {
  const std::string path = write_scene(test_dir() / "scene.json", tiny_box());
  EXPECT_EQ(load_scene(path).model, "quasi_static");
  const Scene sc = load_scene(path, {"model=explicit", "explicit.duration_s=1e-4"});
  EXPECT_EQ(sc.model, "explicit");
  EXPECT_DOUBLE_EQ(sc.settings<ExplicitSettings>("explicit").duration_s, 1e-4);
  EXPECT_EQ(sc.resolved["model"], "explicit");  // summary.json's "parameters"
}

TEST(SceneOverride, ApplyOverrideOnArraysAndValues) {
  json doc = tiny_box();
  apply_override(doc, "regions.1.bc.type=fixed");
  EXPECT_EQ(doc["regions"][1]["bc"]["type"], "fixed");
  apply_override(doc, "regions.0.select.max_m=[1, 1, 2e-4]");
  EXPECT_EQ(doc["regions"][0]["select"]["max_m"], json::parse("[1, 1, 2e-4]"));
  apply_override(doc, "geometry.min_m.2=-1e-3");  // an element of a number array
  EXPECT_DOUBLE_EQ(doc["geometry"]["min_m"][2].get<double>(), -1e-3);
  apply_override(doc, "regions.1={\"name\": \"lid\", \"select\": {\"type\": \"all\"}}");  // a whole element
  EXPECT_EQ(doc["regions"][1]["name"], "lid");
  EXPECT_FALSE(doc["regions"][1].contains("bc"));

  apply_override(doc, "quasi_static.load_steps=7");
  EXPECT_TRUE(doc["quasi_static"]["load_steps"].is_number_integer());
  apply_override(doc, "output.vtk=true");
  EXPECT_EQ(doc["output"]["vtk"], true);
  apply_override(doc, "description=a=b c");  // first '=' splits; not JSON: a string
  EXPECT_EQ(doc["description"], "a=b c");
  apply_override(doc, "name=\"123\"");  // a JSON string
  EXPECT_EQ(doc["name"], "123");
  apply_override(doc, "name=123");  // a number (rejected later by validation)
  EXPECT_TRUE(doc["name"].is_number());
  apply_override(doc, "explicit.dt_s=1e-6");  // creates the missing object
  EXPECT_DOUBLE_EQ(doc["explicit"]["dt_s"].get<double>(), 1e-6);

  EXPECT_THROW(apply_override(doc, "regions.2.name=x"), InputError);    // past the end
  EXPECT_THROW(apply_override(doc, "regions.one.name=x"), InputError);  // not an index
  EXPECT_THROW(apply_override(doc, "regions..name=x"), InputError);     // empty key
  EXPECT_THROW(apply_override(doc, "description.x=1"), InputError);     // inside a string
  EXPECT_THROW(apply_override(doc, "no_equals_sign"), InputError);
  EXPECT_THROW(apply_override(doc, "=1"), InputError);

  // Overrides are applied in order.
  const std::string path = write_scene(test_dir() / "scene.json", tiny_box());
  const Scene sc = load_scene(path, {"regions.1.bc.magnitude_m=2e-5", "regions.1.bc.magnitude_m=3e-5"});
  EXPECT_DOUBLE_EQ(sc.regions[1].magnitude, 3e-5);
}

// ---------------------------------------------------------------------------------------------
// A real run through the CLI

TEST(SceneRun, TinyTubeWritesSummaryAndProbes) {
  const fs::path dir = test_dir();
  const std::string path = write_scene(dir / "tube.json", tiny_tube());
  const fs::path out = dir / "out";
  const CliResult r = cli({"-q", "run", path, "--out", out.string(), "--set", "quasi_static.load_steps=2",
                           "--set", "output.vtk=true"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("summary.json"), std::string::npos) << r.out;

  // probes.csv: header, then one row per output point (step 0 = rest state, then 2 load steps).
  std::ifstream csv(out / "probes.csv");
  ASSERT_TRUE(csv.good());
  std::vector<std::string> lines;
  for (std::string line; std::getline(csv, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 4u);
  const std::vector<std::string> header = split(lines[0]);
  const std::vector<std::string> expected = {"step",
                                             "time_s",
                                             "load_factor",
                                             "end_start_displacement_m",
                                             "end_start_force_n",
                                             "end_finish_displacement_m",
                                             "end_finish_force_n",
                                             "indenter_displacement_m",
                                             "indenter_force_n",
                                             "wall_displacement_m",
                                             "wall_force_n",
                                             "apex_displacement_m",
                                             "iterations",
                                             "inner_iterations",
                                             "residual",
                                             "converged"};
  ASSERT_EQ(header, expected);
  auto col = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  };
  const double magnitude = 5e-5;
  for (std::size_t k = 0; k < 3; ++k) {
    SCOPED_TRACE("row " + std::to_string(k));
    const std::vector<std::string> cells = split(lines[k + 1]);
    ASSERT_EQ(cells.size(), header.size());
    std::vector<double> v;
    for (const auto& c : cells) v.push_back(parse_number(c));
    const double s = 0.5 * static_cast<double>(k);
    EXPECT_EQ(v[col("step")], static_cast<double>(k));
    EXPECT_EQ(v[col("time_s")], 0.0);  // quasi_static: no time
    EXPECT_DOUBLE_EQ(v[col("load_factor")], s);
    // Prescribed displacement, projected on the inward direction: s * magnitude_m.
    EXPECT_NEAR(v[col("indenter_displacement_m")], s * magnitude, 1e-9 * magnitude);
    // Clamped ends do not move; a probe region carries no force.
    EXPECT_EQ(v[col("end_start_displacement_m")], 0.0);
    EXPECT_EQ(v[col("end_finish_displacement_m")], 0.0);
    EXPECT_EQ(v[col("wall_force_n")], 0.0);
    // The apex node lies in the indenter: it moves by -s * magnitude along y.
    EXPECT_NEAR(v[col("apex_displacement_m")], -s * magnitude, 1e-9 * magnitude);
    EXPECT_EQ(v[col("converged")], 1.0);
    if (k == 0) {
      EXPECT_EQ(v[col("iterations")], 0.0);
      EXPECT_NEAR(v[col("indenter_force_n")], 0.0, 1e-12);  // round-off of the rest-state forces
    } else {
      EXPECT_GE(v[col("iterations")], 1.0);
      // Reaction = force the indenter exerts on the tissue, along "inward": it pushes, so positive.
      EXPECT_GT(v[col("indenter_force_n")], 0.0);
      EXPECT_GT(v[col("end_start_force_n")], 0.0);  // no direction: the magnitude
      EXPECT_GT(v[col("wall_displacement_m")], 0.0);
      EXPECT_LE(v[col("residual")], 1e-6);
    }
  }

  // summary.json
  const json summary = json::parse(read_text(out / "summary.json"));
  EXPECT_EQ(summary["scene"], "tiny-tube");
  EXPECT_EQ(summary["scene_file"], path);
  EXPECT_EQ(summary["model"], "quasi_static");
  EXPECT_EQ(summary["parameters"]["quasi_static"]["load_steps"], 2);  // the override is recorded
  EXPECT_GT(summary["nodes"].get<int>(), 0);
  EXPECT_LE(summary["nodes"].get<int>(), 1500);
  EXPECT_EQ(summary["unconverged_steps"], 0);
  EXPECT_EQ(summary["outputs"]["probes_csv"], "probes.csv");
  EXPECT_EQ(summary["outputs"]["vtk"], "vtk/nodes.pvd");
  ASSERT_EQ(summary["steps"].size(), 3u);
  const json& last = summary["steps"][2];
  EXPECT_EQ(last["step"], 2);
  EXPECT_DOUBLE_EQ(last["load_factor"].get<double>(), 1.0);
  EXPECT_NEAR(last["regions"]["indenter"]["displacement_m"].get<double>(), magnitude, 1e-9 * magnitude);
  EXPECT_GT(last["regions"]["indenter"]["force_n"].get<double>(), 0.0);
  EXPECT_EQ(last["regions"]["indenter"]["force_vector_n"].size(), 3u);
  for (const char* key : {"virtual_tetrahedra", "neighbour_pairs", "mean_neighbours", "mean_spacing_m",
                          "support_radius_min_m", "support_radius_max_m", "nodes_with_grown_support",
                          "volume_m3", "mass_kg", "solver", "threads", "timings_s"})
    EXPECT_TRUE(summary.contains(key)) << key;
  EXPECT_FALSE(summary.contains("reference"));

  // VTK series: steps that are multiples of vtk_every (2), and the collection.
  EXPECT_TRUE(fs::exists(out / "vtk" / "nodes_0000.vtu"));
  EXPECT_FALSE(fs::exists(out / "vtk" / "nodes_0001.vtu"));
  EXPECT_TRUE(fs::exists(out / "vtk" / "nodes_0002.vtu"));
  const std::string pvd = read_text(out / "vtk" / "nodes.pvd");
  EXPECT_NE(pvd.find("nodes_0002.vtu"), std::string::npos);
}

TEST(SceneRun, SetModelExplicitRuns) {
  const fs::path dir = test_dir();
  const std::string path = write_scene(dir / "box.json", tiny_box());
  const fs::path out = dir / "out";
  const CliResult r = cli({"-q", "run", path, "--out", out.string(), "--set", "model=explicit", "--set",
                           "explicit.duration_s=1e-4", "--set", "explicit.output_interval_s=5e-5", "--set",
                           "explicit.ramp_time_s=1e-4"});
  ASSERT_EQ(r.code, 0) << r.err;
  const json summary = json::parse(read_text(out / "summary.json"));
  EXPECT_EQ(summary["model"], "explicit");
  EXPECT_EQ(summary["solver"]["model"], "explicit");
  ASSERT_EQ(summary["steps"].size(), 3u);  // rest state + duration / output interval
  std::ifstream csv(out / "probes.csv");
  std::vector<std::string> lines;
  for (std::string line; std::getline(csv, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0],
            "step,time_s,load_factor,base_displacement_m,base_force_n,top_displacement_m,top_force_n,"
            "iterations,inner_iterations,residual,converged");
  const std::vector<std::string> last = split(lines[3]);
  ASSERT_EQ(last.size(), 11u);
  EXPECT_NEAR(parse_number(last[1]), 1e-4, 1e-12);  // time_s
  EXPECT_NEAR(parse_number(last[2]), 1.0, 1e-9);    // load_factor = t / ramp_time_s
  EXPECT_NEAR(parse_number(last[5]), 1e-5, 1e-14);  // top: prescribed displacement along [0, 0, -1]
  EXPECT_GE(parse_number(last[7]), 1.0);            // substeps in this output interval
  EXPECT_EQ(parse_number(last[8]), 0.0);            // no inner iterations
}

}  // namespace
