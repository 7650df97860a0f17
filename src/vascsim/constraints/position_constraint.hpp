#pragma once
// Fixed and prescribed-position constraints (docs/model/19-position-based.md "Boundary conditions"): pin a
// node to a target (its rest position X_i for a clamp, a scripted position for a prescribed displacement), or
// tether it with compliance 1/(k_f V_i) to model surrounding tissue. Mueller et al. 2007 treat a pinned node
// by w = 0; these constraints are for targets that move, or are compliant, or need a reaction force
// (lambda/h^2, e.g. the support reactions of docs/validation.md T14).

#include "vascsim/constraints/xpbd_projection.hpp"

namespace vascsim::constraints {

/// C = |p - target| (m), grad C = (p - target)/|p - target|. With alpha = 0 one projection puts p on the
/// target exactly. The gradient is undefined at C = 0 (returned as zero; the projection then skips);
/// prefer the per-component form for compliant tethers, whose energy is smooth there.
ScalarConstraint<1> position_constraint(const Vec3& p, const Vec3& target);

/// Per-component form: C = p_axis - target_axis (m), grad C = e_axis (axis in 0..2). Three of these
/// pin a node; one or two prescribe only some components (e.g. a sliding support).
ScalarConstraint<1> position_component_constraint(const Vec3& p, const Vec3& target, int axis);

}  // namespace vascsim::constraints
