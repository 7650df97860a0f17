// `vascsim view` with bad input: one clear line and exit code 2, never a crash. Run as a program (popen), so
// the exit code and everything it prints are what a user sees.

#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <string>

#include "support/program_output.hpp"

namespace {

namespace fs = std::filesystem;

using Result = vascsim::test::ProgramOutput;

Result view(const std::string& env, const std::string& args) {
  return vascsim::test::run_program(env, VASCSIM_BINARY_DIR "/vascsim", "view " + args);
}

const std::string kVessel = VASCSIM_SOURCE_DIR "/tests/data/tiny-bent-vessel.json";

void expect_one_line(const Result& r, const std::string& says) {
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(r.lines(), 1u) << r.output;
  EXPECT_NE(r.output.find(says), std::string::npos) << r.output;
}

TEST(ViewerErrors, ASceneWithoutASurfaceOrFile) {
  const fs::path dir = fs::temp_directory_path() / ("vascsim-view-errors-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "no-geometry.json") << R"({ "name": "nothing", "model": "xpbd" })";
  expect_one_line(view("", (dir / "no-geometry.json").string() + " --screenshot x.png"),
                  "key 'geometry': missing");
  expect_one_line(view("", (dir / "absent.json").string()), "cannot open the scene file");
  fs::remove_all(dir);
}

TEST(ViewerErrors, AMissingTextureFileIsOneLineBeforeTheBuild) {
  const Result r =
      view("", kVessel + " --set viewer.texture=missing-wall.png --screenshot x.png --size 64x64");
  expect_one_line(r, "missing-wall.png: no such file");
  EXPECT_NE(r.output.find("texture file"), std::string::npos) << r.output;
}

TEST(ViewerErrors, AnImpossibleWindowSize) {
  expect_one_line(view("", kVessel + " --screenshot x.png --size 0x600"), "window size 0x600 is impossible");
  expect_one_line(view("", kVessel + " --screenshot x.png --size 99999x99999"), "is impossible");
  expect_one_line(view("", kVessel + " --size big"), "--size big: expected WIDTHxHEIGHT");
}

TEST(ViewerErrors, NoDisplayAndNoEgl) {
  // glvnd finds no EGL vendor when pointed at a file that does not exist: as on a machine without Mesa's EGL.
  const Result r =
      view("env -u DISPLAY -u WAYLAND_DISPLAY __EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent/egl.json",
           kVessel + " --size 64x64");
  expect_one_line(r, "cannot render headless");
  EXPECT_NE(r.output.find("xvfb-run"), std::string::npos) << r.output;
}

TEST(ViewerErrors, AModelNoDeviceCanDrive) {
  expect_one_line(view("", kVessel + " --set model=explicit --screenshot x.png --size 64x64"),
                  "cannot be driven by a device");
}

}  // namespace
