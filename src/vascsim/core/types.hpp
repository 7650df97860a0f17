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
using Index = std::int32_t;

/// Node positions, displacements, velocities or forces, one 3-vector per node.
using Vec3Array = std::vector<Vec3>;

}  // namespace vascsim
