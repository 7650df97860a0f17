#pragma once
// Scalar, vector and matrix aliases used throughout vascsim. Everything is SI (m, kg, s, Pa, N).

#include <Eigen/Core>
#include <Eigen/Geometry>
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

}  // namespace vascsim
