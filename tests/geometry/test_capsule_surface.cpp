// The tools' surface in the VTK output: a closed, outward capsule whose enclosed volume and surface points
// match the capsule it draws.

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

#include "vascsim/geometry/capsule_surface.hpp"

namespace vascsim {
namespace {

double enclosed_volume(const RenderSurface& s) {
  double v = 0.0;
  for (const auto& t : s.triangles)
    v += s.rest_vertices[t[0]].dot(s.rest_vertices[t[1]].cross(s.rest_vertices[t[2]])) / 6.0;
  return v;
}

TEST(CapsuleSurface, ClosedOutwardAndOnTheCapsule) {
  const Vec3 a(1e-3, 2e-3, 3e-3), b(1e-3, -4e-3, 3e-3);
  const double r = 1e-3;
  const RenderSurface s = capsule_surface(a, b, r, 24);
  // Closed: every edge is shared by exactly two triangles, once in each direction.
  std::map<std::pair<Index, Index>, int> edges;
  for (const auto& t : s.triangles)
    for (int k = 0; k < 3; ++k) ++edges[{t[k], t[(k + 1) % 3]}];
  for (const auto& [e, n] : edges) {
    EXPECT_EQ(n, 1);
    EXPECT_EQ(edges.count({e.second, e.first}), 1u);
  }
  // Every vertex lies on the capsule (distance to the segment = r, to 1e-12 relative) with its normal
  // outward.
  const Vec3 d = b - a;
  for (std::size_t v = 0; v < s.rest_vertices.size(); ++v) {
    const Vec3& p = s.rest_vertices[v];
    const double t = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    const Vec3 q = a + t * d;
    EXPECT_NEAR((p - q).norm(), r, 1e-12 * r);
    EXPECT_GT(s.rest_normals[v].dot(p - q), 0.99 * r);
  }
  // Outward winding gives a positive enclosed volume, within the polygon's shortfall of the true one: 24
  // segments inscribe a circle with 1.1 % less area, the hemispheres a little more (tolerance 5 %).
  const double exact = std::numbers::pi * r * r * d.norm() + 4.0 / 3.0 * std::numbers::pi * r * r * r;
  EXPECT_GT(enclosed_volume(s), 0.95 * exact);
  EXPECT_LT(enclosed_volume(s), exact);
  EXPECT_EQ(s.outer.size(), s.triangles.size());
}

TEST(CapsuleSurface, AppendKeepsBothPartsIndexedCorrectly) {
  RenderSurface both = capsule_surface(Vec3::Zero(), Vec3::UnitZ(), 0.1, 8);
  const RenderSurface second = capsule_surface(Vec3(5, 0, 0), Vec3(5, 0, 1), 0.1, 8);
  const double v1 = enclosed_volume(both), v2 = enclosed_volume(second);
  append_surface(both, second);
  EXPECT_NEAR(enclosed_volume(both), v1 + v2, 1e-12);  // the same triangles, each with its own vertices
  EXPECT_EQ(both.rest_vertices.size(), 2 * second.rest_vertices.size());
}

}  // namespace
}  // namespace vascsim
