#include "vascsim/constraints/contact_constraint.hpp"

#include <algorithm>
#include <cmath>

namespace vascsim::constraints {

namespace {
// r = p - q (q the closest point of the body's core: sphere centre or capsule segment). scale is a length
// of the problem; |r| <= 1e-14 scale is treated as "on the core", where the normal is undefined.
ContactConstraint from_offset(const Vec3& r, double scale, double body_radius, double node_radius,
                              const Vec3& fallback_normal) {
  const double dist = r.norm();
  ContactConstraint c;
  c.value = dist - body_radius - node_radius;
  c.normal = dist > 1e-14 * scale ? Vec3(r / dist) : fallback_normal;
  c.active = c.value < 0.0;
  return c;
}
}  // namespace

ContactConstraint sphere_contact(const Vec3& p, double node_radius_m, const Sphere& sphere) {
  const Vec3 r = p - sphere.centre;
  return from_offset(r, r.norm() + sphere.radius_m, sphere.radius_m, node_radius_m, Vec3::UnitZ());
}

ContactConstraint capsule_contact(const Vec3& p, double node_radius_m, const Capsule& capsule) {
  const Vec3 ab = capsule.b - capsule.a;
  const double len = ab.norm();
  const Vec3 ap = p - capsule.a;
  const double scale = ap.norm() + len + capsule.radius_m;
  if (!(len > 0.0)) return from_offset(ap, scale, capsule.radius_m, node_radius_m, Vec3::UnitZ());
  const Vec3 axis = ab / len;
  const double s = ap.dot(axis);
  Vec3 r;
  if (s <= 0.0)
    r = ap;  // end cap at a
  else if (s >= len)
    r = p - capsule.b;  // end cap at b
  else
    r = ap - s * axis;  // cylinder: exactly perpendicular to the axis
  return from_offset(r, scale, capsule.radius_m, node_radius_m, axis.unitOrthogonal());
}

}  // namespace vascsim::constraints
