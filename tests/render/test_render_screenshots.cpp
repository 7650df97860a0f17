// Headless screenshots (EGL surfaceless, llvmpipe) of the demo vessel, lit and fluoroscopic. No golden
// images (llvmpipe versions differ): the pictures are checked against what the geometry implies.
//  - Silhouette: the pixels that differ from the background must be the pixels whose centre the projected
//    triangles cover, computed on the CPU from the same camera (render_test_support.hpp). Both sides
//    sample pixel centres, so they differ only where a centre lies within rounding (float on the GPU,
//    double here) of a triangle edge: a few pixels along the outline. Tolerance 1 % of the area (the
//    outline of this picture is about 3 % of it); the measured difference is recorded.
//  - Colour: the vessel's mean colour is far from the background, and reddish (the wall texture).
//  - Fluoroscopy: every pixel grey (R = G = B), the silhouette of wall + catheter as above, the catheter
//    the darkest region, and the attenuation through the vessel's axis as the coefficients predict.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "render_test_support.hpp"

namespace vascsim::render::test {
namespace {

void record(const char* key, double value) {
  ::testing::Test::RecordProperty(key, std::to_string(value));
}

class RenderScreenshot : public HeadlessScene {
 protected:
  // Lit: anything not exactly the clear colour is drawn.
  Silhouette lit_silhouette(const RenderSettings& s, const std::vector<std::uint8_t>& expected) {
    const Image image = render(s);
    const Float3 bg = s.background * 255.0f;
    return compare(image, expected, [&](int, int, const std::uint8_t* p) {
      return std::abs(p[0] - std::lround(bg.x())) > 1 || std::abs(p[1] - std::lround(bg.y())) > 1 ||
             std::abs(p[2] - std::lround(bg.z())) > 1;
    });
  }
  RenderSettings lit_wall_only() const {
    RenderSettings s;
    s.show_tools = false;
    s.show_force = false;
    return s;
  }
  RenderSettings fluoro_exact() const {
    RenderSettings s;
    s.mode = ViewMode::fluoroscopy;
    s.carm_lao_deg = 20.0;
    s.fluoro.noise = 0.0f;  // an exact background level, so one grey level separates object from background
    s.fluoro.vignette = 0.0f;
    return s;
  }
};

TEST_F(RenderScreenshot, LitPictureShowsTheWallSilhouetteInWallColours) {
  const RenderSettings s = lit_wall_only();
  const auto expected = coverage(frame.positions_m, frame.triangles, view_proj(s), kWidth, kHeight);
  const Silhouette sil = lit_silhouette(s, expected);
  record("lit_drawn_px", static_cast<double>(sil.drawn));
  record("lit_expected_px", static_cast<double>(sil.expected));
  record("lit_area_error", sil.relative_error());
  EXPECT_GT(sil.expected, static_cast<std::size_t>(0.03 * kWidth * kHeight));  // the vessel is in view
  EXPECT_TRUE(sil.shows_geometry()) << "drawn " << sil.drawn << " expected " << sil.expected << " both "
                                    << sil.both;
  // The procedural outer wall is reddish: red clearly above blue and green.
  EXPECT_GT(sil.mean_object.x(), sil.mean_object.z() + 40.0) << sil.mean_object.transpose();
  EXPECT_GT(sil.mean_object.x(), sil.mean_object.y() + 40.0) << sil.mean_object.transpose();
}

TEST_F(RenderScreenshot, TheCheckRejectsAPictureWithoutTheWall) {
  // The surface deliberately not drawn (the catheter still is): the silhouette check must fail.
  RenderSettings s = lit_wall_only();
  const auto expected = coverage(frame.positions_m, frame.triangles, view_proj(s), kWidth, kHeight);
  s.show_surface = false;
  s.show_tools = true;
  const Silhouette sil = lit_silhouette(s, expected);
  EXPECT_FALSE(sil.shows_geometry());
  EXPECT_LT(sil.both, sil.expected / 2);  // only where the catheter inside the vessel shows
}

TEST_F(RenderScreenshot, LitWithTheCatheterCoversWallAndCatheter) {
  RenderSettings s;
  s.show_force = false;
  const SolidMesh tools = tool_mesh(frame);
  auto expected = coverage(frame.positions_m, frame.triangles, view_proj(s), kWidth, kHeight);
  const auto tool_px = coverage(tools.positions_m, tools.triangles, view_proj(s), kWidth, kHeight);
  for (std::size_t i = 0; i < expected.size(); ++i) expected[i] |= tool_px[i];
  const Silhouette sil = lit_silhouette(s, expected);
  EXPECT_TRUE(sil.shows_geometry()) << "drawn " << sil.drawn << " expected " << sil.expected;
}

TEST_F(RenderScreenshot, FluoroscopyIsGreyWithTheWallAndCatheterSilhouette) {
  const RenderSettings s = fluoro_exact();
  const Image image = render(s);
  for (std::size_t i = 0; i < image.rgba.size(); i += 4)
    ASSERT_TRUE(image.rgba[i] == image.rgba[i + 1] && image.rgba[i] == image.rgba[i + 2])
        << "pixel " << i / 4;
  const SolidMesh tools = tool_mesh(frame);
  auto expected = coverage(frame.positions_m, frame.triangles, view_proj(s), kWidth, kHeight);
  const auto tool_px = coverage(tools.positions_m, tools.triangles, view_proj(s), kWidth, kHeight);
  for (std::size_t i = 0; i < expected.size(); ++i) expected[i] |= tool_px[i];
  const int background = static_cast<int>(std::lround(255.0f * s.fluoro.background));
  const Silhouette sil =
      compare(image, expected, [&](int, int, const std::uint8_t* p) { return p[0] < background - 1; });
  record("fluoro_area_error", sil.relative_error());
  EXPECT_TRUE(sil.shows_geometry()) << "drawn " << sil.drawn << " expected " << sil.expected << " both "
                                    << sil.both;
  // Darker than the background (attenuation), never brighter.
  EXPECT_LT(sil.mean_object.x(), sil.mean_background.x() - 60.0);
}

TEST_F(RenderScreenshot, FluoroscopyCatheterIsTheDarkestRegion) {
  RenderSettings s;  // the default look: grain and vignette on
  s.mode = ViewMode::fluoroscopy;
  const Image image = render(s);
  const SolidMesh tools = tool_mesh(frame);
  const auto tool_px = coverage(tools.positions_m, tools.triangles, view_proj(s), kWidth, kHeight);
  const auto wall_px = coverage(frame.positions_m, frame.triangles, view_proj(s), kWidth, kHeight);
  double tool_sum = 0, vessel_sum = 0;
  std::size_t tool_n = 0, vessel_n = 0;
  int darkest = 256;
  bool darkest_on_tool = false;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * kWidth + x;
      const int g = image.pixel(x, y)[0];
      ASSERT_EQ(g, image.pixel(x, y)[1]);
      ASSERT_EQ(g, image.pixel(x, y)[2]);
      if (tool_px[i]) {
        tool_sum += g;
        ++tool_n;
      } else if (wall_px[i]) {
        vessel_sum += g;
        ++vessel_n;
      }
      if (g < darkest) {
        darkest = g;
        darkest_on_tool = tool_px[i] != 0;
      }
    }
  ASSERT_GT(tool_n, 100u);
  ASSERT_GT(vessel_n, 1000u);
  record("fluoro_mean_grey_catheter", tool_sum / tool_n);
  record("fluoro_mean_grey_vessel", vessel_sum / vessel_n);
  EXPECT_LT(tool_sum / tool_n, vessel_sum / vessel_n - 30.0);
  EXPECT_TRUE(darkest_on_tool);
}

TEST_F(RenderScreenshot, FluoroscopyGreyThroughTheAxisMatchesTheAttenuationLaw) {
  RenderSettings s = fluoro_exact();
  s.show_tools = false;
  const Image image = render(s);
  // A ray from the source through the centre-line of the first straight leg (5 mm from the entry, along
  // +z): it crosses the wall twice and the lumen once, with chord lengths 2 r / sin(angle to the axis).
  const CameraPose pose = Renderer::pose_for(camera, s);
  const Vec3 point(0.0, 0.0, 5e-3);
  const Vec3 ray = (point - pose.eye_m).normalized();
  const double sin_axis = ray.cross(Vec3::UnitZ()).norm();
  const DemoVesselSpec& spec = demo->spec();
  const double r_out = spec.outer_radius_m, r_in = spec.outer_radius_m - spec.wall_thickness_m;
  const double lumen = 2.0 * r_in / sin_axis, wall = 2.0 * (r_out - r_in) / sin_axis;
  const double a = s.fluoro.mu_contrast_per_m * lumen + s.fluoro.mu_tissue_per_m * wall;
  const double grey = s.fluoro.floor + (s.fluoro.background - s.fluoro.floor) * std::exp(-a);
  const Eigen::Vector4d c = view_proj(s) * point.homogeneous();
  const int x = static_cast<int>((0.5 * c.x() / c.w() + 0.5) * kWidth);
  const int y = static_cast<int>((0.5 - 0.5 * c.y() / c.w()) * kHeight);
  ASSERT_TRUE(x >= 0 && x < kWidth && y >= 0 && y < kHeight);
  // The polygonal wall (the demo's angular resolution) is a few per cent thinner than the circle; the
  // 8-bit picture rounds to 1/255.
  record("fluoro_axis_grey", image.pixel(x, y)[0] / 255.0);
  record("fluoro_axis_grey_expected", grey);
  EXPECT_NEAR(image.pixel(x, y)[0] / 255.0, grey, 0.02) << "attenuation " << a;
}

TEST_F(RenderScreenshot, ForceArrowTurnsRedAboveTheThreshold) {
  RenderSettings s;
  s.show_tools = false;
  auto count_colour = [&](const Image& image, bool red) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < image.rgba.size(); i += 4) {
      const int r = image.rgba[i], g = image.rgba[i + 1], b = image.rgba[i + 2];
      n += red ? (r > 150 && g < 80 && b < 80) : (g > 150 && r < 120 && b < 130);
    }
    return n;
  };
  s.show_surface = false;        // the wall's reds would count
  demo->fill(frame, 0.25, 0.5);  // 0.2 N, threshold 0.5 N
  const Image below = render(s);
  demo->fill(frame, 0.25, 2.0);  // 0.8 N
  const Image above = render(s);
  EXPECT_GT(count_colour(below, false), 50u);
  EXPECT_EQ(count_colour(below, true), 0u);
  EXPECT_GT(count_colour(above, true), 50u);
  EXPECT_EQ(count_colour(above, false), 0u);
}

TEST_F(RenderScreenshot, OverlaysAndColourMapDraw) {
  RenderSettings s = lit_wall_only();
  const Image plain = render(s);
  s.show_colour_map = true;
  const Image mapped = render(s);
  // The colour map replaces the red wall with blues (low displacement almost everywhere): over the wall's
  // pixels, blue minus red turns from negative to positive.
  const auto wall = coverage(frame.positions_m, frame.triangles, view_proj(s), kWidth, kHeight);
  double plain_bmr = 0, mapped_bmr = 0;
  for (std::size_t i = 0; i < wall.size(); ++i) {
    if (!wall[i]) continue;
    plain_bmr += plain.rgba[4 * i + 2] - plain.rgba[4 * i];
    mapped_bmr += mapped.rgba[4 * i + 2] - mapped.rgba[4 * i];
  }
  EXPECT_LT(plain_bmr, 0.0);
  EXPECT_GT(mapped_bmr, 0.0);
  // Cutaway: the inner wall (bluish) becomes visible.
  s.show_colour_map = false;
  s.cutaway = true;
  const Image cut = render(s);
  EXPECT_NE(cut.rgba, plain.rgba);
}

}  // namespace
}  // namespace vascsim::render::test
