#include "vascsim/constraints/distance_constraint.hpp"

namespace vascsim::constraints {

ScalarConstraint<2> distance_constraint(const Vec3& x1, const Vec3& x2, double rest_length) {
  ScalarConstraint<2> c;
  const Vec3 d = x1 - x2;
  const double len = d.norm();
  c.value = len - rest_length;
  const Vec3 n = len > 0.0 ? Vec3(d / len) : Vec3::Zero();
  c.grad[0] = n;
  c.grad[1] = -n;
  return c;
}

}  // namespace vascsim::constraints
