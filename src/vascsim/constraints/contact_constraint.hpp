#pragma once
// One-sided contact of a node sphere against a rigid body given as a signed distance phi
// (docs/model/19-position-based.md, "contact constraints (alpha = 0, only if C < 0)"):
//   C(p) = phi(p) - r_node >= 0,   grad C = grad phi = n (outward unit normal of the body at p)   (m)
// The constraint is active only while C < 0; project it with XpbdParameters::unilateral = true so the
// accumulated lambda stays >= 0. The tissue node is pushed along +n with force lambda n / h^2; the tool
// feels the reaction -lambda n / h^2 (docs/model/19-position-based.md, f_tool = -sum_c lambda_c n_c / h^2).
// Sphere and capsule now; the catheter (a chain of capsules) reuses the capsule.

#include "vascsim/core/types.hpp"

namespace vascsim::constraints {

struct ContactConstraint {
  double value = 0.0;           ///< C = phi(p) - r_node, m (negative: penetration depth)
  Vec3 normal = Vec3::UnitZ();  ///< n = grad phi = grad C, unit, pointing out of the body
  bool active = false;          ///< C < 0
};

struct Sphere {
  Vec3 centre = Vec3::Zero();
  double radius_m = 0.0;
};

/// Segment a-b swept by a ball of radius radius_m.
struct Capsule {
  Vec3 a = Vec3::Zero();
  Vec3 b = Vec3::UnitZ();
  double radius_m = 0.0;
};

/// phi(p) = |p - c| - R, n = (p - c)/|p - c|. At p = c (|p - c| <= 1e-14 of the problem's length scale) the
/// normal is undefined: +z is returned.
ContactConstraint sphere_contact(const Vec3& p, double node_radius_m, const Sphere& sphere);

/// phi(p) = |p - q(p)| - R with q(p) the closest point of segment a-b, n = (p - q)/|p - q|. On the axis
/// (|p - q| <= 1e-14 of the problem's length scale) the normal is undefined: a unit vector perpendicular
/// to the axis is returned. On the cylindrical part n is made exactly perpendicular to the axis. A degenerate
/// segment (a = b) is a sphere.
ContactConstraint capsule_contact(const Vec3& p, double node_radius_m, const Capsule& capsule);

}  // namespace vascsim::constraints
