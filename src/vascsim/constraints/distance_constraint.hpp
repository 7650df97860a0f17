#pragma once
// Stretching (distance) constraint between two nodes: paper Eqs. 13-17 (Zhang et al. 2021), which are
// Mueller et al. 2007 ("Position Based Dynamics", JVCIR 18(2)) section 3.3 (stretching constraint).
// docs/model/16-deviations.md, E10: sound mode applies it to the virtual-tetrahedron edges as an XPBD
// constraint with compliance alpha_e = 1/k_e (m/N); paper-literal mode uses PBD with k' = 1 - (1-k)^{1/n}.

#include "vascsim/constraints/xpbd_projection.hpp"

namespace vascsim::constraints {

/// Paper Eq. 13:  C(x_1, x_2) = |x_1 - x_2| - l_0  (m).
/// Eqs. 14-15:    grad_1 C = n,  grad_2 C = -n,  n = (x_1 - x_2)/|x_1 - x_2|.
/// Projected with the shared routine this gives Eqs. 16-17:
///   Delta x_1 = -w_1/(w_1 + w_2) C n,  Delta x_2 = +w_2/(w_1 + w_2) C n  (PBD with k' = 1 or XPBD, alpha =
///   0).
/// For coincident nodes (|x_1 - x_2| = 0) the direction is undefined: the gradients are returned as zero
/// and the projection skips the constraint (denominator guard).
ScalarConstraint<2> distance_constraint(const Vec3& x1, const Vec3& x2, double rest_length);

}  // namespace vascsim::constraints
