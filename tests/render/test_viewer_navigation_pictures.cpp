// `vascsim navigate SCENE --pictures` (viewer/navigation_pictures.hpp) on a short run of the bundled aorta
// scene: both pictures written at their size, the instrument in the frame they draw, the wire dark on the
// fluoroscopy along the rod's last shape; and without EGL one line and exit code 2.

#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <sstream>

#include "render_test_support.hpp"
#include "support/program_output.hpp"
#include "vascsim/app/cli.hpp"
#include "vascsim/viewer/navigation_pictures.hpp"

namespace vascsim::render::test {
namespace {

namespace fs = std::filesystem;

const std::string kAortaWire = VASCSIM_SOURCE_DIR "/scenes/navigation/aorta-bent-guidewire.json";
// 10 to 30 mm in 0.5 s: 51 frames, the tip not yet at the arch.
const std::string kShortDrive = "instrument.drive=[[0,0.01,0],[0.5,0.03,0]]";

TEST(NavigationPictures, TheFrameHoldsTheWallAndTheRodsLastShape) {
  const Scene scene = load_scene(kAortaWire, {kShortDrive});
  NavigationResult result;
  result.final_positions_m = {Vec3(0.0, 0.0, 0.0), Vec3(0.0, 0.0, 0.01), Vec3(0.001, 0.0, 0.02)};
  const RenderFrame f = viewer::navigation_frame(scene, result);
  EXPECT_GT(f.triangles.size(), 1000u);
  EXPECT_EQ(f.uv.size(), f.positions_m.size());
  ASSERT_EQ(f.instruments.size(), 1u);
  EXPECT_EQ(f.instruments[0].centreline_m.size(), 3u);
  EXPECT_FLOAT_EQ(f.instruments[0].radius_m, 0.5f * 0.889e-3f);
  EXPECT_NO_THROW(validate_frame(f));
}

TEST(NavigationPictures, AShortRunWritesBothPicturesWithTheWireDarkOnTheFluoroscopy) {
  const fs::path dir =
      fs::temp_directory_path() / ("vascsim-navigate-pictures-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  std::ostringstream out, err;
  const int rc =
      run_cli({"-q", "navigate", kAortaWire, "--out", dir.string(), "--pictures", "--set", kShortDrive}, out,
              err, {&viewer::install_navigation_pictures});
  ASSERT_EQ(rc, 0) << err.str();
  EXPECT_NE(out.str().find("wrote " + (dir / "navigation_lit.png").string()), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("wrote " + (dir / "navigation_fluoroscopy.png").string()), std::string::npos);
  const Image lit = read_png(dir / "navigation_lit.png");
  const Image fluoro = read_png(dir / "navigation_fluoroscopy.png");
  ASSERT_EQ(lit.width, 1280);
  ASSERT_EQ(lit.height, 800);
  ASSERT_EQ(fluoro.width, 1280);
  ASSERT_EQ(fluoro.height, 800);
  // The fluoroscopy's darkest pixels are the wire's: far darker than anything the vessel alone gives (its
  // soft-tissue shadow transmits about half).
  int darkest = 255;
  for (int y = 0; y < fluoro.height; ++y)
    for (int x = 0; x < fluoro.width; ++x) darkest = std::min<int>(darkest, fluoro.pixel(x, y)[0]);
  EXPECT_LT(darkest, 60);
  fs::remove_all(dir);
}

TEST(NavigationPictures, WithoutEglTheRunsFilesAreWrittenAndTheErrorIsOneLine) {
  const fs::path dir = fs::temp_directory_path() / ("vascsim-navigate-no-egl-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  // glvnd finds no EGL vendor when pointed at a file that does not exist: as on a machine without Mesa's EGL.
  const vascsim::test::ProgramOutput r = vascsim::test::run_program(
      "env -u DISPLAY -u WAYLAND_DISPLAY __EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent/egl.json",
      VASCSIM_BINARY_DIR "/vascsim",
      "-q navigate " + kAortaWire + " --out " + dir.string() + " --pictures --set '" + kShortDrive + "'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("vascsim: error: --pictures: cannot render headless"), std::string::npos)
      << r.output;
  EXPECT_EQ(r.lines(), 2u) << r.output;  // the run's summary line, then the error
  EXPECT_TRUE(fs::exists(dir / "instrument_final.csv"));
  EXPECT_FALSE(fs::exists(dir / "navigation_lit.png"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace vascsim::render::test
