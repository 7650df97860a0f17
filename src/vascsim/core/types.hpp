#pragma once
// Scalar, vector and matrix aliases used throughout vascsim. Everything is SI (m, kg, s, Pa, N).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <vector>

namespace vascsim {

using Real = double;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Vec9 = Eigen::Matrix<double, 9, 1>;  ///< a 3x3 matrix stored column by column, or a quadratic basis
using Mat9 = Eigen::Matrix<double, 9, 9>;  ///< a linear map between two Vec9 (e.g. a tangent dP/dF)
using Index = std::int32_t;

/// Node positions, displacements, velocities or forces, one 3-vector per node.
using Vec3Array = std::vector<Vec3>;

/// Whether two node arrays hold the very same state, compared value for value (what a cache of work done at a
/// state checks before reusing it).
inline bool same_state(const Vec3Array& a, const Vec3Array& b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](const Vec3& p, const Vec3& q) {
           return p.x() == q.x() && p.y() == q.y() && p.z() == q.z();
         });
}

}  // namespace vascsim
