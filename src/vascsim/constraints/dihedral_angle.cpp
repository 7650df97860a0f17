#include "vascsim/constraints/dihedral_angle.hpp"

#include <cmath>

namespace vascsim::constraints {

ScalarConstraint<4> dihedral_angle(const Vec3& x1, const Vec3& x2, const Vec3& x3, const Vec3& x4) {
  ScalarConstraint<4> c;
  const Vec3 n1 = (x1 - x3).cross(x1 - x4), n2 = (x2 - x4).cross(x2 - x3), e = x4 - x3;
  const double n1sq = n1.squaredNorm(), n2sq = n2.squaredNorm(), len = e.norm();
  if (!(n1sq > 0.0) || !(n2sq > 0.0) || !(len > 0.0)) return c;
  c.value = std::atan2(n1.cross(n2).dot(e) / len, n1.dot(n2));
  const Vec3 m1 = n1 / n1sq, m2 = n2 / n2sq;
  c.grad[0] = -len * m1;
  c.grad[1] = -len * m2;
  c.grad[2] = -((x1 - x4).dot(e) / len * m1 + (x2 - x4).dot(e) / len * m2);
  c.grad[3] = (x1 - x3).dot(e) / len * m1 + (x2 - x3).dot(e) / len * m2;
  return c;
}

}  // namespace vascsim::constraints
