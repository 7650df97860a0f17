// Headless pictures of a real scene through `vascsim view`'s code path (run_cli with the view command, in
// process, EGL): tests/data/tiny-bent-vessel.json (a coarse bent vein, 1,560 nodes) at rest (--paused: the
// surface drawn is then exactly the rest surface, so the expected silhouette is known), lit and fluoroscopic.
// No golden images (llvmpipe versions differ): pixel statistics against the background and the silhouette the
// rest surface covers under the viewer's camera, rasterised on the CPU (render_test_support.hpp).

#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <sstream>

#include <fmt/format.h>

#include "render_test_support.hpp"
#include "vascsim/app/cli.hpp"
#include "vascsim/run/body_builder.hpp"
#include "vascsim/scene/scene.hpp"
#include "vascsim/viewer/view_command.hpp"

namespace vascsim::render::test {
namespace {

namespace fs = std::filesystem;

const std::string kScene = std::string(VASCSIM_SOURCE_DIR) + "/tests/data/tiny-bent-vessel.json";
constexpr int kWidth = 320, kHeight = 200;
constexpr double kYaw = 30.0, kPitch = 20.0;  // a view that shows the bend

// `vascsim -q view tiny-bent-vessel.json --paused --screenshot ... <extra>`, in process; the picture.
Image view(const std::vector<std::string>& extra) {
  const fs::path png = fs::temp_directory_path() / ("vascsim-view-" + std::to_string(::getpid()) + ".png");
  std::vector<std::string> args = {"-q",           "view",
                                   kScene,         "--paused",
                                   "--screenshot", png.string(),
                                   "--size",       fmt::format("{}x{}", kWidth, kHeight),
                                   "--yaw",        std::to_string(kYaw),
                                   "--pitch",      std::to_string(kPitch)};
  args.insert(args.end(), extra.begin(), extra.end());
  std::ostringstream out, err;
  const int rc = run_cli(args, out, err, {&viewer::add_view_command});
  EXPECT_EQ(rc, 0) << err.str();
  Image image = read_png(png);
  fs::remove(png);
  return image;
}

// The rest surface's coverage under the viewer's camera: framed on the surface, turned by --yaw/--pitch.
std::vector<std::uint8_t> expected_silhouette(const RenderSettings& settings) {
  const Body body = build_body(load_scene(kScene).geometry);
  std::vector<Float3> positions;
  Bounds b;
  b.min = b.max = body.surface->rest_vertices.front();
  for (const Vec3& p : body.surface->rest_vertices) {
    positions.push_back(p.cast<float>());
    b.min = b.min.cwiseMin(p.cast<float>().cast<double>());
    b.max = b.max.cwiseMax(p.cast<float>().cast<double>());
  }
  std::vector<std::array<std::uint32_t, 3>> triangles;
  for (const auto& t : body.surface->triangles)
    triangles.push_back({static_cast<std::uint32_t>(t[0]), static_cast<std::uint32_t>(t[1]),
                         static_cast<std::uint32_t>(t[2])});
  OrbitCamera camera;
  camera.fit(b);
  camera.orbit(-kYaw / 0.3, (kPitch - 15.0) / 0.3);
  const CameraPose pose = Renderer::pose_for(camera, settings);
  const Eigen::Matrix4d view_proj = pose.projection(static_cast<double>(kWidth) / kHeight) * pose.view();
  return coverage(positions, triangles, view_proj, kWidth, kHeight);
}

// Lit: anything that is not the clear colour is drawn.
Silhouette lit_silhouette(const Image& image, const std::vector<std::uint8_t>& expected) {
  const Float3 bg = RenderSettings{}.background * 255.0f;
  return compare(image, expected, [&](int, int, const std::uint8_t* p) {
    return std::abs(p[0] - std::lround(bg.x())) > 1 || std::abs(p[1] - std::lround(bg.y())) > 1 ||
           std::abs(p[2] - std::lround(bg.z())) > 1;
  });
}

// Silhouette tolerances as the renderer's own tests (test_render_screenshots.cpp): both sides sample pixel
// centres, so the areas differ only along the outline by rounding (float on the GPU, double here); 1 % of the
// area, 99 % of the expected pixels drawn, the wall's mean colour 20 levels (of 255) from the background.
TEST(ViewerScreenshot, LitPictureOfARealSceneShowsTheVesselSilhouette) {
  const Image image = view({});
  ASSERT_EQ(image.width, kWidth);
  const auto expected = expected_silhouette(RenderSettings{});
  const Silhouette s = lit_silhouette(image, expected);
  std::printf(
      "[ viewer   ] lit: drawn %zu px, expected %zu px, both %zu, area error %.4f, mean wall (%.0f %.0f "
      "%.0f)\n",
      s.drawn, s.expected, s.both, s.relative_error(), s.mean_object.x(), s.mean_object.y(),
      s.mean_object.z());
  EXPECT_GT(s.expected, static_cast<std::size_t>(0.05 * kWidth * kHeight));  // the vessel fills the picture
  EXPECT_TRUE(s.shows_geometry()) << "drawn " << s.drawn << " expected " << s.expected << " both " << s.both;
  EXPECT_GT(s.mean_object.x(), s.mean_object.z() + 40.0);  // the procedural wall is reddish
}

// Checked once on purpose: a picture without the wall (--no-surface) fails the same check.
TEST(ViewerScreenshot, TheCheckFailsWhenTheSurfaceIsNotDrawn) {
  const Image image = view({"--no-surface"});
  const Silhouette s = lit_silhouette(image, expected_silhouette(RenderSettings{}));
  EXPECT_FALSE(s.shows_geometry());
  EXPECT_EQ(s.drawn, 0u);  // nothing else in this scene (no tool)
}

// Fluoroscopy (LAO 30): the vessel is what differs from the same picture without the wall (same grain and
// vignette: the background is identical pixel for pixel). Every pixel is grey. The vessel is darker than
// where it is absent. The outline differs from the geometric one where the path through the wall's rim is so
// short that the attenuation changes the grey by less than one level: tolerance 3 % of the area and 97 % of
// the expected pixels (measured below).
TEST(ViewerScreenshot, FluoroscopyOfARealSceneShowsTheContrastFilledVessel) {
  const std::vector<std::string> fluoro = {"--mode", "fluoro", "--lao", "30"};
  const Image image = view(fluoro);
  std::vector<std::string> without = fluoro;
  without.push_back("--no-surface");
  const Image reference = view(without);
  ASSERT_EQ(image.rgba.size(), reference.rgba.size());
  for (std::size_t i = 0; i < image.rgba.size(); i += 4)
    ASSERT_TRUE(image.rgba[i] == image.rgba[i + 1] && image.rgba[i] == image.rgba[i + 2])
        << "pixel " << i / 4;
  RenderSettings s;
  s.mode = ViewMode::fluoroscopy;
  s.carm_lao_deg = 30.0;
  const auto expected = expected_silhouette(s);
  const Silhouette sil = compare(
      image, expected, [&](int x, int y, const std::uint8_t* p) { return p[0] != reference.pixel(x, y)[0]; });
  std::printf(
      "[ viewer   ] fluoroscopy: drawn %zu px, expected %zu px, both %zu, area error %.4f, grey %.0f vs "
      "%.0f\n",
      sil.drawn, sil.expected, sil.both, sil.relative_error(), sil.mean_object.x(), sil.mean_background.x());
  EXPECT_GT(sil.expected, static_cast<std::size_t>(0.05 * kWidth * kHeight));
  EXPECT_LE(sil.relative_error(), 0.03);
  EXPECT_GE(sil.both, 0.97 * sil.expected);
  EXPECT_LT(sil.mean_object.x(), sil.mean_background.x() - 20.0);  // attenuated: darker
  std::size_t brighter = 0;
  for (std::size_t i = 0; i < image.rgba.size(); i += 4) brighter += image.rgba[i] > reference.rgba[i];
  EXPECT_EQ(brighter, 0u);  // matter only ever attenuates
}

}  // namespace
}  // namespace vascsim::render::test
