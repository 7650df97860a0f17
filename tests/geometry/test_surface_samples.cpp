// Quadrature points on a surface for embedded contact (geometry/surface_samples.hpp): they carry the whole
// area, lie on the curved wall the vertex normals describe (not on the flat chords between the vertices) and
// stay on flat faces at creases.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "vascsim/core/error.hpp"
#include "vascsim/geometry/capsule_surface.hpp"
#include "vascsim/geometry/surface_samples.hpp"

namespace vascsim {
namespace {

double mesh_area(const RenderSurface& s) {
  double a = 0.0;
  for (const auto& t : s.triangles)
    a += 0.5 * (s.rest_vertices[t[1]] - s.rest_vertices[t[0]])
                   .cross(s.rest_vertices[t[2]] - s.rest_vertices[t[0]])
                   .norm();
  return a;
}

// A capsule of radius 1 mm drawn with 24 segments: its flat triangles lie up to r (1 - cos(pi/24)) = 8.6 um
// inside the capsule. The samples, lifted by Phong tessellation with shape factor 1/2, must lie within 0.5 um
// of it (the lift's error is of fourth order in the segment's half angle, 0.1 um for a circle; the sphere's
// caps have irregular triangles, hence 0.5 um): 1/17 of the chords' sag, so a flat sampling fails.
TEST(SurfaceSamples, CarryTheAreaAndLieOnTheCurvedWall) {
  const Vec3 a(0, 0, 0), b(0, 0, 4e-3);
  const double r = 1e-3;
  const RenderSurface s = capsule_surface(a, b, r, 24);
  const SurfaceSamples samples = sample_surface(s, 0.1e-3);
  ASSERT_GT(samples.positions.size(), s.triangles.size());
  double area = 0.0, worst = 0.0;
  for (std::size_t v = 0; v < samples.positions.size(); ++v) {
    area += samples.area_m2[v];
    const Vec3& p = samples.positions[v];
    const double t = std::clamp(p.z() / 4e-3, 0.0, 1.0);
    worst = std::max(worst, std::abs((p - Vec3(0, 0, 4e-3 * t)).norm() - r));
    EXPECT_NEAR(samples.normals[v].norm(), 1.0, 1e-12);
  }
  EXPECT_NEAR(area, mesh_area(s),
              1e-10 * area);  // the sub-triangles tile each triangle (round-off of 1e5 terms)
  EXPECT_LT(worst, 0.5e-6) << "farthest sample from the capsule";
  EXPECT_EQ(samples.triangle.size(), samples.positions.size());
  EXPECT_EQ(samples.barycentric.size(), samples.positions.size());
}

// A cube whose vertex normals are the corners' diagonals (55 degrees off every face): creases, so its samples
// stay on the faces, exactly.
TEST(SurfaceSamples, CreasesKeepTheFacesFlat) {
  RenderSurface cube;
  for (int k = 0; k < 8; ++k) {
    const Vec3 p((k & 1) ? 0.5 : -0.5, (k & 2) ? 0.5 : -0.5, (k & 4) ? 0.5 : -0.5);
    cube.rest_vertices.push_back(p);
    cube.rest_normals.push_back(p.normalized());
  }
  // Two outward triangles per face.
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    cube.triangles.push_back({f[0], f[1], f[2]});
    cube.triangles.push_back({f[0], f[2], f[3]});
  }
  const SurfaceSamples samples = sample_surface(cube, 0.2);
  double area = 0.0;
  for (std::size_t v = 0; v < samples.positions.size(); ++v) {
    area += samples.area_m2[v];
    EXPECT_DOUBLE_EQ(samples.positions[v].cwiseAbs().maxCoeff(), 0.5) << "sample " << v << " left its face";
  }
  EXPECT_NEAR(area, 6.0, 1e-12);
  EXPECT_THROW(sample_surface(cube, 0.0), InputError);
  EXPECT_THROW(sample_surface(cube, -1.0), InputError);
}

// A graded lattice's surface: a large and a small flat triangle (legs 10 mm and 0.5 mm). One spacing from the
// whole surface's mean edge (a third of it, 2.7 mm) leaves the small triangle a single sample; with at least
// a third of its own mean edge apart it gets ceil(0.707 / (0.569 / 3)) = 4 per side, 16 samples, as a uniform
// lattice of its size would, while the large triangle's sampling and the total area do not change.
TEST(SurfaceSamples, EachTriangleAtLeastAFractionOfItsOwnEdgeApart) {
  RenderSurface s;
  s.rest_vertices = {Vec3(0, 0, 0),     Vec3(10e-3, 0, 0),   Vec3(0, 10e-3, 0),
                     Vec3(20e-3, 0, 0), Vec3(20.5e-3, 0, 0), Vec3(20e-3, 0.5e-3, 0)};
  s.triangles = {{0, 1, 2}, {3, 4, 5}};
  const double leg = 10e-3, small = 0.5e-3, diag = std::sqrt(2.0);
  const double mean = (2.0 * leg + diag * leg + 2.0 * small + diag * small) / 6.0;
  auto count_on = [](const SurfaceSamples& samples, Index t) {
    return std::count(samples.triangle.begin(), samples.triangle.end(), t);
  };
  const SurfaceSamples plain = sample_surface(s, mean / 3.0);
  const SurfaceSamples own = sample_surface(s, mean / 3.0, 1.0 / 3.0);
  EXPECT_EQ(count_on(plain, 1), 1);
  EXPECT_EQ(count_on(own, 1), 16);
  EXPECT_EQ(count_on(own, 0), count_on(plain, 0));
  double area = 0.0;
  for (double a : own.area_m2) area += a;
  EXPECT_NEAR(area, mesh_area(s), 1e-12 * area);
  EXPECT_NEAR(own.spacing_min_m, (2.0 + diag) * small / 3.0 / 3.0, 1e-15);
  EXPECT_DOUBLE_EQ(plain.spacing_min_m, mean / 3.0);
  EXPECT_THROW(sample_surface(s, mean / 3.0, -0.1), InputError);
}

}  // namespace
}  // namespace vascsim
