#pragma once
// The integration constraint (the discrete divergence theorem) of the point-primitive quadrature. Under a
// uniform stress sigma (Pa) the internal force on node k is -sigma c_k with
//   c_k = sum_i sum_q W_iq dF_iq/dx_k = sum_i sum_q W_iq (d_ik + sum_g o_iqg e_ik,g)        (m^2)
// (W_iq = V_i / points, docs/model/04-volumes.md section 4.4 and docs/model/08-forces.md). A
// Galerkin-consistent quadrature has c_k = 0 at every node inside the body and c_k = the boundary integral of
// the node's share of the outward normal on its surface, so a uniformly stressed body is in equilibrium under
// its surface tractions alone. Where c_k != 0 inside, the quadrature adds spurious body forces proportional
// to the stress (docs/validation.md, "The integration constraint through the wall").

#include <vector>

#include "vascsim/model/discretization.hpp"

namespace vascsim {

/// c_k for every node, m^2.
Vec3Array integration_residuals(const Discretization& disc);

struct IntegrationConstraintReport {
  Index interior_nodes = 0;       ///< nodes on no boundary face of the virtual tetrahedra
  double boundary_area_m2 = 0.0;  ///< mean lumped boundary area of the boundary nodes, m^2 (the scale)
  double interior_max = 0.0;      ///< max |c_k| inside over that scale (0 when consistent)
  double interior_rms = 0.0;      ///< root mean square of the same
};

/// The interior residuals against the boundary nodes' mean share of the surface (the virtual tetrahedra's
/// boundary faces decide which nodes are inside).
IntegrationConstraintReport integration_constraint_report(const Discretization& disc);

}  // namespace vascsim
