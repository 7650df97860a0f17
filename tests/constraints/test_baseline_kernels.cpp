// The constraint kernels the baselines add (docs/model/25-baselines.md): the dihedral angle of two triangles
// (the surface mass-spring's flexion term) and the tet volume (the PBD volume constraint), against central
// differences.

#include <gtest/gtest.h>

#include "vascsim/constraints/dihedral_angle.hpp"
#include "vascsim/constraints/tet_volume_constraint.hpp"
#include "vascsim/geometry/node_cloud.hpp"

namespace vascsim::constraints {
namespace {

// Central differences of kernel(x) over every coordinate of the four nodes, against its gradient.
template <class Kernel>
void expect_gradient_matches(const std::array<Vec3, 4>& x, Kernel kernel, double tolerance) {
  const auto c = kernel(x);
  const double eps = 1e-6;
  for (int k = 0; k < 4; ++k)
    for (int d = 0; d < 3; ++d) {
      auto xp = x, xm = x;
      xp[k][d] += eps;
      xm[k][d] -= eps;
      const double fd = (kernel(xp).value - kernel(xm).value) / (2 * eps);
      EXPECT_NEAR(c.grad[k][d], fd, tolerance) << "node " << k << " component " << d;
    }
}

// Central differences with step 1e-6 m on O(1 m) coordinates: truncation ~1e-12 and round-off ~1e-10
// relative, so 1e-7 absolute on gradients of order 1 is far above both and far below any sign or factor
// error.
TEST(BaselineKernels, DihedralAngleGradientMatchesCentralDifferences) {
  std::array<Vec3, 4> x = {Vec3(0.3, 1.0, 0.2), Vec3(-0.1, -0.9, 0.5), Vec3(0.0, 0.0, 0.0),
                           Vec3(1.1, 0.1, -0.05)};
  auto angle = [](const std::array<Vec3, 4>& p) { return dihedral_angle(p[0], p[1], p[2], p[3]); };
  EXPECT_GT(std::abs(angle(x).value), 0.1);  // a bent hinge
  expect_gradient_matches(x, angle, 1e-7);
  // Coplanar triangles on opposite sides of the edge: theta = 0.
  EXPECT_NEAR(dihedral_angle(Vec3(0.5, 1, 0), Vec3(0.5, -1, 0), Vec3(0, 0, 0), Vec3(1, 0, 0)).value, 0.0,
              1e-15);
}

TEST(BaselineKernels, TetVolumeGradientMatchesCentralDifferences) {
  TetPositions x = {Vec3(0, 0, 0), Vec3(1, 0.1, 0), Vec3(0.2, 1, 0.1), Vec3(0.1, 0.2, 1.2)};
  EXPECT_NEAR(tet_volume_constraint(x, 0.1).value, vascsim::signed_volume(x[0], x[1], x[2], x[3]) - 0.1,
              1e-15);
  expect_gradient_matches(
      x, [](const TetPositions& p) { return tet_volume_constraint(p, 0.1); }, 1e-9);
}

}  // namespace
}  // namespace vascsim::constraints
