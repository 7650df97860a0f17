#include "vascsim/constraints/position_constraint.hpp"

#include <stdexcept>

namespace vascsim::constraints {

ScalarConstraint<1> position_constraint(const Vec3& p, const Vec3& target) {
  const Vec3 r = p - target;
  const double len = r.norm();
  ScalarConstraint<1> c;
  c.value = len;
  c.grad[0] = len > 0.0 ? Vec3(r / len) : Vec3::Zero();
  return c;
}

ScalarConstraint<1> position_component_constraint(const Vec3& p, const Vec3& target, int axis) {
  if (axis < 0 || axis > 2)
    throw std::invalid_argument("position_component_constraint: axis must be 0, 1 or 2");
  ScalarConstraint<1> c;
  c.value = p[axis] - target[axis];
  c.grad[0] = Vec3::Unit(axis);
  return c;
}

}  // namespace vascsim::constraints
