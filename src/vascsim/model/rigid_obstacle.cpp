#include "vascsim/model/rigid_obstacle.hpp"

#include <fmt/format.h>
#include <cmath>

#include "vascsim/core/error.hpp"

namespace vascsim {

RigidObstacle make_catheter(const std::string& name, const Vec3& tip_m, const Vec3& direction,
                            double diameter_m, double length_m) {
  if (!(diameter_m > 0.0) || !std::isfinite(diameter_m))
    throw InputError(fmt::format("catheter '{}': the diameter must be > 0 (got {} m)", name, diameter_m));
  if (!(length_m >= diameter_m) || !std::isfinite(length_m))
    throw InputError(fmt::format("catheter '{}': length_m ({} m) must be at least the diameter ({} m)", name,
                                 length_m, diameter_m));
  if (!(direction.norm() > 0.0) || !direction.allFinite())
    throw InputError(fmt::format("catheter '{}': the direction must be a non-zero vector", name));
  const Vec3 d = direction.normalized();
  RigidObstacle c;
  c.name = name;
  c.shape = RigidObstacle::Shape::Capsule;
  c.catheter = true;
  c.radius_m = 0.5 * diameter_m;
  c.length_m = length_m;
  c.tool_point_m = tip_m;
  c.a_m = tip_m - c.radius_m * d;  // centre of the rounded tip
  c.b_m = tip_m - (length_m - c.radius_m) * d;
  return c;
}

constraints::Capsule obstacle_at(const RigidObstacle& obstacle, double s) {
  const Vec3 shift = s * obstacle.motion_m;
  const Vec3 b = obstacle.shape == RigidObstacle::Shape::Sphere ? obstacle.a_m : obstacle.b_m;
  return {obstacle.a_m + shift, b + shift, obstacle.radius_m + obstacle.node_radius_m};
}

Vec3 tool_point_at(const RigidObstacle& obstacle, double s) {
  return obstacle.tool_point_m + s * obstacle.motion_m;
}

Eigen::Quaterniond orientation_pointing(const Vec3& direction) {
  return Eigen::Quaterniond::FromTwoVectors(Vec3(0.0, 0.0, -1.0), direction.normalized());
}

constraints::Capsule obstacle_posed(const RigidObstacle& obstacle, const Vec3& position_m,
                                    const Eigen::Quaterniond& orientation) {
  if (obstacle.shape == RigidObstacle::Shape::Sphere) {
    const Vec3 c = position_m + (obstacle.a_m - obstacle.tool_point_m);
    return {c, c, obstacle.radius_m + obstacle.node_radius_m};
  }
  const Eigen::Quaterniond q = orientation.normalized();
  if (obstacle.catheter) {
    const Vec3 d = q * Vec3(0.0, 0.0, -1.0);
    return {position_m - obstacle.radius_m * d, position_m - (obstacle.length_m - obstacle.radius_m) * d,
            obstacle.radius_m + obstacle.node_radius_m};
  }
  return {position_m + q * (obstacle.a_m - obstacle.tool_point_m),
          position_m + q * (obstacle.b_m - obstacle.tool_point_m),
          obstacle.radius_m + obstacle.node_radius_m};
}

}  // namespace vascsim
