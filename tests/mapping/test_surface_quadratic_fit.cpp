// The curvature correction of a surface's linear interpolation (mapping/surface_quadratic_fit.hpp): with it a
// point's shape functions reproduce quadratic fields along the surface, sum to one and pass through the
// nodes.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "vascsim/core/error.hpp"
#include "vascsim/mapping/surface_quadratic_fit.hpp"

namespace vascsim {
namespace {

constexpr double kL = 1e-3;  // lattice spacing, m

// A lattice of nodes on a cylinder of radius R (axis z; R = 0: the plane z = 0), 11 x 11, spacing kL along
// the surface, centred on the point (R, 0, 0) of the cylinder (the origin of the plane), normals outward.
SurfaceNodes lattice(double R) {
  SurfaceNodes s;
  for (int i = -5; i <= 5; ++i)
    for (int j = -5; j <= 5; ++j) {
      s.node.push_back(static_cast<Index>(s.node.size()));
      if (R == 0.0) {
        s.position_m.emplace_back(i * kL, j * kL, 0.0);
        s.normal.emplace_back(0.0, 0.0, 1.0);
      } else {
        const double t = i * kL / R;
        s.position_m.emplace_back(R * std::cos(t), R * std::sin(t), j * kL);
        s.normal.emplace_back(std::cos(t), std::sin(t), 0.0);
      }
    }
  return s;
}

Index at(int i, int j) {
  return static_cast<Index>((i + 5) * 11 + (j + 5));
}

// The point with barycentric weights w on the triangle of nodes (0,0), (1,0), (0,1) (lattice indices), its
// position interpolated on the triangle (the samples lie on the flat triangle or near it) and the normal of
// node (0,0).
struct Point {
  Vec3 p, n;
  SurfaceCorners corners;
  std::array<Index, 3> node;
};

Point point_on(const SurfaceNodes& s, const Vec3& w) {
  Point pt;
  pt.node = {at(0, 0), at(1, 0), at(0, 1)};
  pt.p = Vec3::Zero();
  for (int k = 0; k < 3; ++k) {
    pt.corners.position_m[static_cast<std::size_t>(k)] =
        s.position_m[static_cast<std::size_t>(pt.node[static_cast<std::size_t>(k)])];
    pt.p += w[k] * pt.corners.position_m[static_cast<std::size_t>(k)];
  }
  pt.corners.weight = w;
  pt.n = s.normal[static_cast<std::size_t>(at(0, 0))];
  return pt;
}

// sum_i phi_i f_i with phi the barycentric weights plus the correction.
template <class F>
double interpolate(const Point& pt, const SurfaceFitRow& row, const SurfaceNodes& s, F&& f) {
  double sum = 0.0;
  for (int k = 0; k < 3; ++k)
    sum += pt.corners.weight[k] *
           f(s.position_m[static_cast<std::size_t>(pt.node[static_cast<std::size_t>(k)])]);
  for (std::size_t k = 0; k < row.node.size(); ++k)
    sum += row.phi[k] * f(s.position_m[static_cast<std::size_t>(row.node[k])]);
  return sum;
}

TEST(SurfaceQuadraticFit, ReproducesQuadraticFieldsOnAPlaneWhereLinearInterpolationDoesNot) {
  const SurfaceNodes s = lattice(0.0);
  const auto f = [](const Vec3& X) {
    const double x = X.x() / kL, y = X.y() / kL;
    return 1.0 + 2.0 * x - 3.0 * y + 4.0 * x * x + 5.0 * x * y + 6.0 * y * y;
  };
  for (const Vec3& w : {Vec3(1.0 / 3, 1.0 / 3, 1.0 / 3), Vec3(0.7, 0.2, 0.1), Vec3(0.1, 0.45, 0.45)}) {
    const Point pt = point_on(s, w);
    const auto rows = surface_curvature_rows(s, {pt.p}, {pt.n}, {pt.corners});
    ASSERT_FALSE(rows[0].node.empty());
    const double exact = f(pt.p);
    double linear = 0.0;
    for (int k = 0; k < 3; ++k) linear += w[k] * f(pt.corners.position_m[static_cast<std::size_t>(k)]);
    // Round-off of a 6x6 solve on O(1) scaled coordinates and fields of O(10): 1e-10 of the field.
    EXPECT_NEAR(interpolate(pt, rows[0], s, f), exact, 1e-10 * 10.0);
    // The linear interpolation misses by the chord's sag, O(1) here: the test can tell the two apart.
    EXPECT_GT(std::abs(linear - exact), 0.1);
    double sum = 0.0;
    for (double phi : rows[0].phi) sum += phi;
    EXPECT_NEAR(sum, 0.0, 1e-12);  // the correction adds nothing to a constant: partition of unity
  }
}

TEST(SurfaceQuadraticFit, ReproducesQuadraticFieldsOfTheTangentCoordinatesOnACylinder) {
  // On a curved surface the fit's coordinates are the tangent plane's, so fields quadratic in the arc length
  // and z are reproduced to the surface's curvature times the spacing squared; R = 12 mm, kL = 1 mm, as the
  // aorta's.
  const double R = 12e-3;
  const SurfaceNodes s = lattice(R);
  const auto f = [&](const Vec3& X) {
    const double arc = R * std::atan2(X.y(), X.x()) / kL, z = X.z() / kL;
    return 0.5 - arc + 2.0 * z + 3.0 * arc * arc - 1.0 * arc * z + 2.0 * z * z;
  };
  const Point pt = point_on(s, Vec3(0.4, 0.3, 0.3));
  const auto rows = surface_curvature_rows(s, {pt.p}, {pt.n}, {pt.corners});
  ASSERT_FALSE(rows[0].node.empty());
  const double exact = f(pt.p);
  double linear = 0.0;
  for (int k = 0; k < 3; ++k)
    linear += pt.corners.weight[k] * f(pt.corners.position_m[static_cast<std::size_t>(k)]);
  const double corrected = interpolate(pt, rows[0], s, f);
  // The projection onto the tangent plane shortens an arc s by s^3 / (6 R^2): for s of two spacings 1 % of
  // the fitted curvature terms, so within 2 % of the linear interpolation's error.
  EXPECT_LT(std::abs(corrected - exact), 0.02 * std::abs(linear - exact))
      << corrected << " " << exact << " " << linear;
}

TEST(SurfaceQuadraticFit, PassesThroughTheNodesAndSkipsTheOtherFace) {
  SurfaceNodes s = lattice(0.0);
  // The wall's other face, a tenth of a spacing below, facing the other way: never in the fit.
  const std::size_t n = s.node.size();
  for (std::size_t k = 0; k < n; ++k) {
    s.node.push_back(static_cast<Index>(n + k));
    s.position_m.push_back(s.position_m[k] - Vec3(0.0, 0.0, 0.1 * kL));
    s.normal.emplace_back(0.0, 0.0, -1.0);
  }
  const Point corner = point_on(s, Vec3(1.0, 0.0, 0.0));
  const auto rows =
      surface_curvature_rows(s, {corner.p, point_on(s, Vec3(0.2, 0.3, 0.5)).p}, {corner.n, corner.n},
                             {corner.corners, point_on(s, Vec3(0.2, 0.3, 0.5)).corners});
  for (double phi : rows[0].phi) EXPECT_NEAR(phi, 0.0, 1e-13);  // at a corner the correction vanishes
  ASSERT_FALSE(rows[1].node.empty());
  for (Index i : rows[1].node) EXPECT_LT(i, static_cast<Index>(n));
}

TEST(SurfaceQuadraticFit, LeavesARowEmptyWhenTooFewNodesFitAndRefusesBadInput) {
  SurfaceNodes s;
  for (int k = 0; k < 5; ++k) {  // five nodes on a line cannot fit six monomials
    s.node.push_back(k);
    s.position_m.emplace_back(k * kL, 0.0, 0.0);
    s.normal.emplace_back(0.0, 0.0, 1.0);
  }
  const SurfaceCorners c{{Vec3(0, 0, 0), Vec3(kL, 0, 0), Vec3(0, kL, 0)}, Vec3(0.4, 0.3, 0.3)};
  const auto rows = surface_curvature_rows(s, {Vec3(0.3 * kL, 0.3 * kL, 0)}, {Vec3::UnitZ()}, {c});
  EXPECT_TRUE(rows[0].node.empty());
  EXPECT_THROW(surface_curvature_rows(s, {Vec3::Zero()}, {}, {c}), InputError);
  const SurfaceCorners flat{{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()}, Vec3(1, 0, 0)};
  EXPECT_THROW(surface_curvature_rows(s, {Vec3::Zero()}, {Vec3::UnitZ()}, {flat}), InputError);
}

}  // namespace
}  // namespace vascsim
