#include "vascsim/constraints/tet_neo_hookean_constraint.hpp"

#include <string>

#include "vascsim/core/error.hpp"
#include "vascsim/core/tensor_algebra.hpp"

namespace vascsim::constraints {

namespace {
Mat3 edge_matrix(const TetPositions& x) {
  Mat3 D;
  D.col(0) = x[1] - x[0];
  D.col(1) = x[2] - x[0];
  D.col(2) = x[3] - x[0];
  return D;
}

// Chain rule through F = D_s D_m^{-1}: dC = P : dD_s D_m^{-1} = (P D_m^{-T}) : dD_s.
ScalarConstraint<4> from_stress(double value, const Mat3& P, const Mat3& Dm_inv) {
  const Mat3 H = P * Dm_inv.transpose();
  ScalarConstraint<4> c;
  c.value = value;
  c.grad[1] = H.col(0);
  c.grad[2] = H.col(1);
  c.grad[3] = H.col(2);
  c.grad[0] = -(c.grad[1] + c.grad[2] + c.grad[3]);
  return c;
}
}  // namespace

TetRestShape tet_rest_shape(const TetPositions& X) {
  const Mat3 Dm = edge_matrix(X);
  const double det = Dm.determinant();
  const double scale = Dm.colwise().norm().prod();
  if (!(det > 1e-12 * scale))
    throw NumericalError(
        "tet_rest_shape: degenerate or inverted rest tetrahedron (det D_m = " + std::to_string(det) + ")");
  return {Dm.inverse(), det / 6.0};
}

Mat3 tet_deformation_gradient(const TetPositions& x, const Mat3& Dm_inv) {
  return edge_matrix(x) * Dm_inv;
}

ScalarConstraint<4> tet_hydrostatic_constraint(const TetPositions& x, const Mat3& Dm_inv,
                                               double lame_lambda_pa, double shear_modulus_pa) {
  const Mat3 F = tet_deformation_gradient(x, Dm_inv);
  const double gamma = 1.0 + shear_modulus_pa / lame_lambda_pa;
  return from_stress(F.determinant() - gamma, cofactor(F), Dm_inv);
}

ScalarConstraint<4> tet_deviatoric_constraint(const TetPositions& x, const Mat3& Dm_inv) {
  const Mat3 F = tet_deformation_gradient(x, Dm_inv);
  const double r = F.norm();
  return from_stress(r, r > 0.0 ? Mat3(F / r) : Mat3::Zero(), Dm_inv);
}

}  // namespace vascsim::constraints
