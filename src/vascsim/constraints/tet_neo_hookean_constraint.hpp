#pragma once
// XPBD stable neo-Hookean constraints of a virtual tetrahedron (docs/model/19-position-based.md (B) and E11):
// Macklin & Mueller 2021, "A Constraint-based Formulation of Stable Neo-Hookean Materials", MIG 2021
// (the hydrostatic/deviatoric constraint pair). With F = D_s D_m^{-1} (Sifakis & Barbic 2012,
// "FEM simulation of 3D deformable solids", SIGGRAPH 2012 course notes):
//   C_H = det F - (1 + mu/lambda),   compliance alpha_H = 1 / (lambda V_T)     (dimensionless C)
//   C_D = sqrt(tr F^T F),            compliance alpha_D = 1 / (mu V_T)
// so that C_H^2/(2 alpha_H) + C_D^2/(2 alpha_D) = V_T [lambda/2 (J - 1 - mu/lambda)^2 + mu/2 tr F^T F],
// the stable neo-Hookean energy up to a constant. Compliances are in 1/J = 1/(N·m).

#include "vascsim/constraints/energy_constraint.hpp"
#include "vascsim/core/error.hpp"

namespace vascsim::constraints {

/// Rest data of a tet: D_m^{-1} with D_m = [X_1 - X_0, X_2 - X_0, X_3 - X_0] (1/m) and the rest volume
/// V_T = det(D_m)/6 (m^3). Throws NumericalError for a degenerate or inverted rest tet.
struct TetRestShape {
  Mat3 Dm_inv;
  double volume = 0.0;
};
TetRestShape tet_rest_shape(const TetPositions& X);

/// F = D_s D_m^{-1}, D_s = [x_1 - x_0, x_2 - x_0, x_3 - x_0].
Mat3 tet_deformation_gradient(const TetPositions& x, const Mat3& Dm_inv);

/// Hydrostatic constraint C_H = det F - gamma, gamma = 1 + mu/lambda (Macklin & Mueller 2021).
/// dC_H/dF = cof(F); grad_{1..3} = columns of cof(F) D_m^{-T}, grad_0 = -(grad_1 + grad_2 + grad_3).
ScalarConstraint<4> tet_hydrostatic_constraint(const TetPositions& x, const Mat3& Dm_inv,
                                               double lame_lambda_pa, double shear_modulus_pa);

/// Deviatoric constraint C_D = sqrt(tr F^T F) = |F|_F (Macklin & Mueller 2021).
/// dC_D/dF = F / C_D (zero gradient, i.e. skipped, for F = 0).
ScalarConstraint<4> tet_deviatoric_constraint(const TetPositions& x, const Mat3& Dm_inv);

/// alpha_H = 1/(lambda V_T), 1/J.
inline double tet_hydrostatic_compliance(double lame_lambda_pa, double rest_volume_m3) {
  return 1.0 / (lame_lambda_pa * rest_volume_m3);
}
/// alpha_D = 1/(mu V_T), 1/J.
inline double tet_deviatoric_compliance(double shear_modulus_pa, double rest_volume_m3) {
  return 1.0 / (shear_modulus_pa * rest_volume_m3);
}

}  // namespace vascsim::constraints
