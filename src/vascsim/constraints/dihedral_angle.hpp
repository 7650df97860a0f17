#pragma once
// The dihedral angle of two triangles sharing an edge, and its gradient (Bridson, Marino, Fedkiw, "Simulation
// of clothing with folds and wrinkles", SCA 2003, section 4): nodes x_1, x_2 opposite the shared edge x_3 ->
// x_4, the triangles (x_3, x_4, x_1) and (x_4, x_3, x_2) oriented alike, n_1 = (x_1 - x_3) x (x_1 - x_4), n_2
// = (x_2 - x_4) x (x_2 - x_3), e = x_4 - x_3:
//   theta = atan2((n_1 x n_2) . e/|e|, n_1 . n_2)     (rad; 0 when the two triangles are coplanar)
//   grad_1 = -|e| n_1/|n_1|^2,  grad_2 = -|e| n_2/|n_2|^2,
//   grad_3 = -[(x_1 - x_4).e/|e| n_1/|n_1|^2 + (x_2 - x_4).e/|e| n_2/|n_2|^2],
//   grad_4 = +[(x_1 - x_3).e/|e| n_1/|n_1|^2 + (x_2 - x_3).e/|e| n_2/|n_2|^2]      (1/m).
// The bending (flexion) term of the surface mass-spring baseline; a degenerate triangle or edge gives zero
// gradients.

#include "vascsim/constraints/xpbd_projection.hpp"

namespace vascsim::constraints {

ScalarConstraint<4> dihedral_angle(const Vec3& x1, const Vec3& x2, const Vec3& x3, const Vec3& x4);

}  // namespace vascsim::constraints
