// CPU parts of the renderer (no GL): the lumen caps and tool meshes
// the fluoroscopy pass relies on (closed, consistently oriented), the colour map, and frame validation.

#include <gtest/gtest.h>

#include <map>
#include <numbers>

#include "vascsim/core/error.hpp"
#include "vascsim/render/colour_map.hpp"
#include "vascsim/render/demo_vessel.hpp"
#include "vascsim/render/lumen_caps.hpp"
#include "vascsim/render/tool_geometry.hpp"

namespace vascsim::render {
namespace {

using Triangles = std::vector<std::array<std::uint32_t, 3>>;

// Every directed edge appears once and its reverse once: closed and consistently oriented.
bool closed_and_oriented(const Triangles& tris) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  for (const auto& [e, n] : directed) {
    if (n != 1) return false;
    if (directed.find({e.second, e.first}) == directed.end()) return false;
  }
  return true;
}

TEST(RenderGeometry, LumenOfTheDemoVesselIsClosedWithTheLumenVolume) {
  DemoVesselSpec spec;
  spec.target_triangles = 8000;
  const DemoVessel demo(spec);
  RenderFrame f;
  demo.fill(f, 0.25, 0.0);  // no indentation
  const Triangles lumen = lumen_surface(f.triangles, f.outer);
  ASSERT_GT(lumen.size(), 100u);
  EXPECT_TRUE(closed_and_oriented(lumen));
  // Oriented like the inner wall (into the lumen): negative volume, about pi r^2 L (polygonal: a bit less).
  const double r = spec.outer_radius_m - spec.wall_thickness_m;
  const double volume = -signed_volume(f.positions_m, lumen);
  const double expected = std::numbers::pi * r * r * demo.vessel().length_m;
  EXPECT_NEAR(volume / expected, 1.0, 0.02);
  // The whole wall is closed too (the fluoroscopy pass sums its path length).
  EXPECT_TRUE(closed_and_oriented(f.triangles));
  EXPECT_GT(signed_volume(f.positions_m, f.triangles), 0.0);
}

TEST(RenderGeometry, LumenIsEmptyWithoutInnerFlags) {
  const Triangles tris = {{0, 1, 2}};
  EXPECT_TRUE(lumen_surface(tris, {}).empty());
  EXPECT_TRUE(lumen_surface(tris, {1, 1, 1}).empty());
}

TEST(RenderGeometry, CapsuleIsClosedOutwardWithTheCapsuleVolume) {
  for (bool rounded : {true, false}) {
    SolidMesh m;
    ToolCapsule t;
    t.back_m = Float3(0.01f, -0.02f, 0.0f);
    t.tip_m = Float3(0.03f, 0.01f, 0.02f);
    t.radius_m = 1e-3f;
    t.rounded_tip = rounded;
    append_capsule(m, t, 48);
    // Closed by position (the flat discs have their own vertices): weld to check.
    std::map<std::array<float, 3>, std::uint32_t> weld;
    Triangles welded;
    for (const auto& tri : m.triangles) {
      std::array<std::uint32_t, 3> w{};
      for (int k = 0; k < 3; ++k) {
        const Float3& p = m.positions_m[tri[k]];
        w[k] =
            weld.emplace(std::array<float, 3>{p.x(), p.y(), p.z()}, static_cast<std::uint32_t>(weld.size()))
                .first->second;
      }
      welded.push_back(w);
    }
    EXPECT_TRUE(closed_and_oriented(welded)) << "rounded " << rounded;
    const double r = t.radius_m, length = (t.tip_m - t.back_m).norm();
    const double expected =
        rounded ? std::numbers::pi * r * r * (length - r) + 2.0 / 3.0 * std::numbers::pi * r * r * r
                : std::numbers::pi * r * r * length;
    EXPECT_NEAR(signed_volume(m.positions_m, m.triangles) / expected, 1.0, 0.01) << "rounded " << rounded;
    // The apex is the tip.
    float far = 0.0f;
    for (const Float3& p : m.positions_m)
      far = std::max(far, (p - t.back_m).dot((t.tip_m - t.back_m).normalized()));
    EXPECT_NEAR(far, length, 1e-6);
  }
}

TEST(RenderGeometry, ArrowSpansItsVector) {
  SolidMesh m;
  append_arrow(m, Float3(1, 2, 3), Float3(0, 0, 0.5f), 0.01f);
  ASSERT_FALSE(m.triangles.empty());
  float lo = 1e9f, hi = -1e9f;
  for (const Float3& p : m.positions_m) {
    lo = std::min(lo, p.z());
    hi = std::max(hi, p.z());
  }
  EXPECT_NEAR(lo, 3.0f, 1e-6);
  EXPECT_NEAR(hi, 3.5f, 1e-6);
  SolidMesh none;
  append_arrow(none, Float3::Zero(), Float3::Zero(), 0.01f);  // zero force: nothing
  EXPECT_TRUE(none.triangles.empty());
}

TEST(RenderGeometry, ColourMapRunsFromBlueToRedAndClamps) {
  const Float3 lo = colour_map(0.0f), hi = colour_map(1.0f);
  EXPECT_GT(lo.z(), lo.x());
  EXPECT_GT(hi.x(), hi.z());
  EXPECT_EQ(colour_map(-1.0f), lo);
  EXPECT_EQ(colour_map(2.0f), hi);
  EXPECT_NE(colour_map_glsl().find("vec3 colour_map(float t)"), std::string::npos);
}

TEST(RenderGeometry, ValidateFrameNamesTheInconsistentArray) {
  RenderFrame f;
  f.positions_m = {Float3::Zero(), Float3::UnitX(), Float3::UnitY()};
  f.triangles = {{0, 1, 2}};
  EXPECT_NO_THROW(validate_frame(f));
  f.uv = {Float2::Zero()};
  EXPECT_THROW(validate_frame(f), InputError);
  f.uv.clear();
  f.triangles = {{0, 1, 3}};
  try {
    validate_frame(f);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("triangle 0 uses vertex 3"), std::string::npos);
  }
  f.triangles = {{0, 1, 2}};
  f.positions_m[1].x() = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(validate_frame(f), InputError);
}

TEST(RenderGeometry, ComputedNormalsPointOutOfTheWall) {
  DemoVesselSpec spec;
  spec.target_triangles = 4000;
  const DemoVessel demo(spec);
  RenderFrame f;
  demo.fill(f, 0.25, 0.0);
  // On the straight first leg (z < leg), the outer wall's normal is radial outward from the z axis.
  int checked = 0;
  for (std::size_t i = 0; i < f.positions_m.size(); ++i) {
    const Float3& p = f.positions_m[i];
    if (!f.outer[i] || p.z() < 2e-3f || p.z() > 10e-3f) continue;
    const Float3 radial = Float3(p.x(), p.y(), 0.0f).normalized();
    EXPECT_GT(f.normals[i].dot(radial), 0.99f);
    ++checked;
  }
  EXPECT_GT(checked, 50);
}

}  // namespace
}  // namespace vascsim::render
