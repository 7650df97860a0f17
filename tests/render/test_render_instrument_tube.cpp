// A flexible instrument in the renderer (render/tool_geometry.hpp): its tube mesh on the CPU (rings at
// the radius with outward normals, closed and outward-oriented, no twist round a bend, degenerate input
// dropped), and headless pictures of it inside the demo vessel: darker than the vessel behind it along its
// projected path in fluoroscopy, and in its own colour in front of the cut-away wall in the lit view.

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

#include "render_test_support.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/geometry/centerline.hpp"
#include "vascsim/render/tool_geometry.hpp"

namespace vascsim::render::test {
namespace {

using TubeTriangles = std::vector<std::array<std::uint32_t, 3>>;

// Welds vertices at equal positions (the end discs have their own), then: every directed edge once and its
// reverse once.
bool tube_is_closed_and_oriented(const SolidMesh& m) {
  std::map<std::array<float, 3>, std::uint32_t> weld;
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const auto& tri : m.triangles) {
    std::array<std::uint32_t, 3> w{};
    for (int k = 0; k < 3; ++k) {
      const Float3& p = m.positions_m[tri[k]];
      w[k] = weld.emplace(std::array<float, 3>{p.x(), p.y(), p.z()}, static_cast<std::uint32_t>(weld.size()))
                 .first->second;
    }
    for (int k = 0; k < 3; ++k) ++directed[{w[k], w[(k + 1) % 3]}];
  }
  for (const auto& [e, n] : directed)
    if (n != 1 || directed.count({e.second, e.first}) == 0) return false;
  return true;
}

// The area of a regular polygon of `sides` inscribed in a circle of radius r.
double polygon_area(int sides, double r) {
  return 0.5 * sides * r * r * std::sin(2.0 * std::numbers::pi / sides);
}

TEST(InstrumentTube, AStraightTubeHasARingPerPointAtTheRadiusWithOutwardNormals) {
  constexpr int kSides = 12;
  constexpr int kPoints = 5;
  const Float3 axis = Float3(1.0f, 2.0f, 2.0f) / 3.0f;
  const Float3 start(0.01f, -0.02f, 0.03f);
  const float r = 0.4e-3f, step = 2e-3f, length = step * (kPoints - 1);
  InstrumentTube tube;
  tube.radius_m = r;
  for (int i = 0; i < kPoints; ++i) tube.centreline_m.push_back(start + step * static_cast<float>(i) * axis);
  SolidMesh m;
  append_tube(m, tube, kSides);

  // A ring per point; each end disc a ring of its own (flat normals) and a centre.
  ASSERT_EQ(m.positions_m.size(), static_cast<std::size_t>(kPoints * kSides + 2 * (kSides + 1)));
  ASSERT_EQ(m.normals.size(), m.positions_m.size());
  EXPECT_EQ(m.triangles.size(), static_cast<std::size_t>(2 * kSides * (kPoints - 1) + 2 * kSides));
  int side = 0, end = 0;
  for (std::size_t v = 0; v < m.positions_m.size(); ++v) {
    SCOPED_TRACE(::testing::Message() << "vertex " << v);
    const Float3 d = m.positions_m[v] - start;
    const float along = d.dot(axis);
    const Float3 across = d - along * axis;
    const Float3& n = m.normals[v];
    EXPECT_NEAR(n.norm(), 1.0f, 1e-5f);
    if (std::abs(n.dot(axis)) < 1e-4f) {  // the side: at the radius, the normal pointing away from the axis
      ++side;
      EXPECT_NEAR(across.norm(), r, 1e-4f * r);
      EXPECT_LT((n - across / r).norm(), 1e-3f);
    } else {  // an end disc: at an end, inside the radius, facing out of the tube
      ++end;
      const bool at_start = along < 0.5f * length;
      EXPECT_NEAR(along, at_start ? 0.0f : length, 1e-4f * r);
      EXPECT_LE(across.norm(), r * (1.0f + 1e-4f));
      EXPECT_LT((n - (at_start ? -axis : axis)).norm(), 1e-5f);
    }
  }
  EXPECT_EQ(side, kPoints * kSides);
  EXPECT_EQ(end, 2 * (kSides + 1));
  EXPECT_TRUE(tube_is_closed_and_oriented(m));
  // Outward: the enclosed volume is positive, the polygonal prism's.
  EXPECT_NEAR(signed_volume(m.positions_m, m.triangles) / (polygon_area(kSides, r) * length), 1.0, 1e-3);
}

TEST(InstrumentTube, ABentTubeHasUnitOutwardNormalsAndDoesNotTwist) {
  // A helix: 270 degrees round a 5 mm radius while rising 6 mm, in 80 points of 0.3 mm, one given twice.
  constexpr int kSides = 12;
  const float r = 0.4e-3f;
  std::vector<Float3> points;
  for (int i = 0; i < 80; ++i) {
    const float a = 1.5f * std::numbers::pi_v<float> * static_cast<float>(i) / 79.0f;
    points.emplace_back(5e-3f * std::cos(a), 5e-3f * std::sin(a), 6e-3f * static_cast<float>(i) / 79.0f);
  }
  InstrumentTube tube;
  tube.radius_m = r;
  tube.centreline_m = points;
  tube.centreline_m.insert(tube.centreline_m.begin() + 40, points[40]);  // a zero-length segment
  SolidMesh m;
  append_tube(m, tube, kSides);
  ASSERT_EQ(m.positions_m.size(), static_cast<std::size_t>(80 * kSides + 2 * (kSides + 1)));
  for (const Float3& n : m.normals) {
    ASSERT_TRUE(n.allFinite());
    EXPECT_NEAR(n.norm(), 1.0f, 1e-5f);
  }
  // The rings follow the start disc (a ring and a centre): ring i's vertex k is its point plus r times its
  // normal, and the same vertex of the next ring is no farther than the points are apart (a twist or a
  // sheared quad would move it round the tube).
  const std::size_t first_ring = kSides + 1;
  for (std::size_t i = 0; i < points.size(); ++i)
    for (std::size_t k = 0; k < kSides; ++k) {
      const std::size_t v = first_ring + i * kSides + k;
      EXPECT_LT((m.positions_m[v] - (points[i] + r * m.normals[v])).norm(), 1e-4f * r) << "ring " << i;
      if (i + 1 < points.size()) {
        const float apart = (points[i + 1] - points[i]).norm();
        EXPECT_LT((m.positions_m[v + kSides] - m.positions_m[v]).norm(), 1.1f * apart) << "ring " << i;
      }
    }
  EXPECT_TRUE(tube_is_closed_and_oriented(m));
  const double arc = std::hypot(1.5 * std::numbers::pi * 5e-3, 6e-3);
  EXPECT_NEAR(signed_volume(m.positions_m, m.triangles) / (polygon_area(kSides, r) * arc), 1.0, 0.01);
}

TEST(InstrumentTube, FewerThanTwoDistinctPointsDrawNothing) {
  for (const std::vector<Float3>& line : {std::vector<Float3>{}, std::vector<Float3>{Float3::Ones()},
                                          std::vector<Float3>{Float3::Ones(), Float3::Ones()}}) {
    InstrumentTube tube;
    tube.centreline_m = line;
    SolidMesh m;
    append_tube(m, tube);
    EXPECT_TRUE(m.positions_m.empty());
    EXPECT_TRUE(m.triangles.empty());
  }
}

TEST(InstrumentTube, FramesBoundAndValidateTheirInstruments) {
  RenderFrame f;
  InstrumentTube tube;
  tube.radius_m = 1e-3f;
  tube.centreline_m = {Float3(0.0f, 0.0f, 0.0f), Float3(0.0f, 0.0f, 0.05f)};
  f.instruments.push_back(tube);
  const Bounds b = scene_bounds(f);
  EXPECT_NEAR(b.min.z(), -1e-3, 1e-9);
  EXPECT_NEAR(b.max.z(), 0.051, 1e-9);
  EXPECT_NO_THROW(validate_frame(f));
  f.instruments[0].radius_m = 0.0f;
  EXPECT_THROW(validate_frame(f), InputError);
  f.instruments[0].radius_m = 1e-3f;
  f.instruments[0].centreline_m[1].x() = std::nanf("");
  EXPECT_THROW(validate_frame(f), InputError);
}

// The demo vessel without its catheter, a 1 mm wire along its centre-line instead.
class InstrumentPicture : public HeadlessScene {
 protected:
  void SetUp() override {
    HeadlessScene::SetUp();
    frame.tools.clear();
    frame.force.reset();
    const DemoVesselSpec& spec = demo->spec();
    const Centerline line = bent_centerline(spec.bend_radius_m, spec.bend_angle_deg, spec.leg_length_m);
    InstrumentTube wire;
    wire.radius_m = 0.5e-3f;
    for (int i = 0; i <= 60; ++i)
      wire.centreline_m.push_back(line.position(line.length() * (0.1 + 0.8 * i / 60.0)).cast<float>());
    frame.instruments.push_back(wire);
  }

  // The pixels of the wire's centre-line points under `settings`' camera, its ends left out (the discs);
  // only those inside the picture.
  std::vector<std::array<int, 2>> path_pixels(const RenderSettings& settings) const {
    std::vector<std::array<int, 2>> px;
    const auto& points = frame.instruments.front().centreline_m;
    for (std::size_t i = 2; i + 2 < points.size(); ++i) {
      const Eigen::Vector4d c = view_proj(settings) * points[i].cast<double>().homogeneous();
      const int x = static_cast<int>(std::floor((0.5 * c.x() / c.w() + 0.5) * kWidth));
      const int y = static_cast<int>(std::floor((0.5 - 0.5 * c.y() / c.w()) * kHeight));
      if (x >= 0 && x < kWidth && y >= 0 && y < kHeight) px.push_back({x, y});
    }
    return px;
  }
};

TEST_F(InstrumentPicture, FluoroscopyIsDarkerAlongTheInstrumentsPath) {
  RenderSettings s;
  s.mode = ViewMode::fluoroscopy;
  s.fluoro.noise = 0.0f;  // exact levels: the difference is the wire's alone
  s.fluoro.vignette = 0.0f;
  const Image with = render(s);
  s.show_tools = false;  // the instruments are drawn and X-rayed with the tools
  const Image without = render(s);
  s.show_tools = true;
  const auto path = path_pixels(s);
  ASSERT_GT(path.size(), 40u);
  const int background = static_cast<int>(std::lround(255.0 * s.fluoro.background));
  for (const auto& [x, y] : path) {
    SCOPED_TRACE(::testing::Message() << "pixel " << x << ", " << y);
    const int g = with.pixel(x, y)[0], g0 = without.pixel(x, y)[0];
    EXPECT_LT(g, background - 100);
    // The contrast-filled lumen behind it transmits about a quarter, the 1 mm wire a further 30 %.
    EXPECT_LT(g, g0 - 15);
  }
}

TEST_F(InstrumentPicture, TheLitViewShowsTheInstrumentInsideTheCutAwayWall) {
  RenderSettings s;
  s.cutaway = true;
  const Image with = render(s);
  s.show_tools = false;
  const Image without = render(s);
  s.show_tools = true;
  const auto path = path_pixels(s);
  ASSERT_GT(path.size(), 40u);
  double least_green_over_red = 255.0;
  for (const auto& [x, y] : path) {
    SCOPED_TRACE(::testing::Message() << "pixel " << x << ", " << y);
    const std::uint8_t *p = with.pixel(x, y), *q = without.pixel(x, y);
    const Eigen::Vector3d drawn(p[0], p[1], p[2]), wall(q[0], q[1], q[2]);
    // The inner wall is drawn there without the wire (cut open, not the background) ...
    const Float3 bg = s.background * 255.0f;
    EXPECT_GT((wall - bg.cast<double>()).norm(), 20.0);
    // ... and the wire hides it, in its own teal (green well above red; the wall's inside is lavender, its
    // cut red: green below red).
    EXPECT_GT((drawn - wall).norm(), 40.0);
    EXPECT_GT(drawn.y() - drawn.x(), 30.0);
    EXPECT_LT(wall.y() - wall.x(), 0.0);
    least_green_over_red = std::min(least_green_over_red, drawn.y() - drawn.x());
  }
  ::testing::Test::RecordProperty("lit_instrument_least_green_over_red",
                                  std::to_string(least_green_over_red));
}

}  // namespace
}  // namespace vascsim::render::test
