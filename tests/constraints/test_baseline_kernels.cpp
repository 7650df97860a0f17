// The constraint kernels the baselines add (docs/model.md section 25): the dihedral angle of two triangles (the
// surface mass-spring's flexion term) and the tet volume (the PBD volume constraint), against central
// differences.

#include <gtest/gtest.h>

#include "vascsim/constraints/dihedral_angle.hpp"
#include "vascsim/constraints/tet_volume_constraint.hpp"
#include "vascsim/geometry/node_cloud.hpp"

namespace vascsim::constraints {
namespace {

// Central differences with step 1e-6 m on O(1 m) coordinates: truncation ~1e-12 and round-off ~1e-10 relative,
// so 1e-7 absolute on gradients of order 1 is far above both and far below any sign or factor error.
TEST(BaselineKernels, DihedralAngleGradientMatchesCentralDifferences) {
  std::array<Vec3, 4> x = {Vec3(0.3, 1.0, 0.2), Vec3(-0.1, -0.9, 0.5), Vec3(0.0, 0.0, 0.0), Vec3(1.1, 0.1, -0.05)};
  const auto c = dihedral_angle(x[0], x[1], x[2], x[3]);
  EXPECT_GT(std::abs(c.value), 0.1);  // a bent hinge
  const double eps = 1e-6;
  for (int k = 0; k < 4; ++k)
    for (int d = 0; d < 3; ++d) {
      auto xp = x, xm = x;
      xp[k][d] += eps;
      xm[k][d] -= eps;
      const double fd = (dihedral_angle(xp[0], xp[1], xp[2], xp[3]).value -
                         dihedral_angle(xm[0], xm[1], xm[2], xm[3]).value) / (2 * eps);
      EXPECT_NEAR(c.grad[k][d], fd, 1e-7) << "node " << k << " component " << d;
    }
  // Coplanar triangles on opposite sides of the edge: theta = 0.
  EXPECT_NEAR(dihedral_angle(Vec3(0.5, 1, 0), Vec3(0.5, -1, 0), Vec3(0, 0, 0), Vec3(1, 0, 0)).value, 0.0, 1e-15);
}

TEST(BaselineKernels, TetVolumeGradientMatchesCentralDifferences) {
  TetPositions x = {Vec3(0, 0, 0), Vec3(1, 0.1, 0), Vec3(0.2, 1, 0.1), Vec3(0.1, 0.2, 1.2)};
  const auto c = tet_volume_constraint(x, 0.1);
  EXPECT_NEAR(c.value, vascsim::signed_volume(x[0], x[1], x[2], x[3]) - 0.1, 1e-15);
  const double eps = 1e-6;
  for (int k = 0; k < 4; ++k)
    for (int d = 0; d < 3; ++d) {
      auto xp = x, xm = x;
      xp[k][d] += eps;
      xm[k][d] -= eps;
      const double fd = (tet_volume_constraint(xp, 0.1).value - tet_volume_constraint(xm, 0.1).value) / (2 * eps);
      EXPECT_NEAR(c.grad[k][d], fd, 1e-9) << "node " << k << " component " << d;
    }
}

}  // namespace
}  // namespace vascsim::constraints
