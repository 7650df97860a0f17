#include "vascsim/constraints/tet_volume_constraint.hpp"

namespace vascsim::constraints {

ScalarConstraint<4> tet_volume_constraint(const TetPositions& x, double rest_volume_m3) {
  ScalarConstraint<4> c;
  const Vec3 e1 = x[1] - x[0], e2 = x[2] - x[0], e3 = x[3] - x[0];
  c.grad[1] = e2.cross(e3) / 6.0;
  c.grad[2] = e3.cross(e1) / 6.0;
  c.grad[3] = e1.cross(e2) / 6.0;
  c.grad[0] = -(c.grad[1] + c.grad[2] + c.grad[3]);
  c.value = e1.dot(c.grad[1]) - rest_volume_m3;
  return c;
}

}  // namespace vascsim::constraints
