#pragma once
// Volume conservation of one tetrahedron (the PBD volume constraint, Mueller et al. 2007, "Position Based
// Dynamics", JVCIR 18(2), section 4.4 with the 1/6 kept in V):
//   C(x_0..x_3) = V(x) - V_0,  V(x) = (x_1 - x_0) . ((x_2 - x_0) x (x_3 - x_0)) / 6   (m^3)
//   grad_1 C = (x_2 - x_0) x (x_3 - x_0) / 6,  grad_2 C = (x_3 - x_0) x (x_1 - x_0) / 6,
//   grad_3 C = (x_1 - x_0) x (x_2 - x_0) / 6,  grad_0 C = -(grad_1 + grad_2 + grad_3)   (m^2).
// A sum of these over many tets is the volume of their union (the global constraint of the filling baseline).
// As an XPBD constraint with compliance alpha = V_0 / K (m^3/Pa) its energy is K V_0 (dV/V_0)^2 / 2: bulk
// modulus K.

#include "vascsim/constraints/energy_constraint.hpp"
#include "vascsim/constraints/xpbd_projection.hpp"

namespace vascsim::constraints {

ScalarConstraint<4> tet_volume_constraint(const TetPositions& x, double rest_volume_m3);

}  // namespace vascsim::constraints
