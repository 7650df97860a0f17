#pragma once
// Rigid tools in contact with the tissue (docs/model/22-contact.md): spheres, capsules and the catheter, a
// capsule with a rounded tip on a short shaft. A tool is placed either by the load factor s (translated by
// s * motion_m: quasi-static indentation, scripted pushes) or by a device pose (the haptic session), and
// both models that support contact (xpbd, quasi_static) see the same geometry through obstacle_contact().
//
// Contact is between the tool and the interior nodes, which are points (node-sphere radius 0): the vessel
// scenes put node layers on the inner and outer wall surfaces, so the tool meets the wall where it is
// rendered (docs/haptics.md, "Where contact is detected"). quasi_static can instead let the tools meet the
// wall's surface between the nodes (contact.surface "embedded", embedded_contact.hpp).

#include <Eigen/Geometry>
#include <string>

#include "vascsim/constraints/contact_constraint.hpp"
#include "vascsim/core/types.hpp"

namespace vascsim {

/// 1 French = 1/3 mm of outer diameter.
constexpr double kMetresPerFrench = 1e-3 / 3.0;

struct RigidObstacle {
  enum class Shape { Sphere, Capsule };
  std::string name;
  Shape shape = Shape::Sphere;
  double radius_m = 0.0;
  Vec3 a_m = Vec3::Zero();       ///< sphere centre, or capsule segment start, at s = 0 (m)
  Vec3 b_m = Vec3::Zero();       ///< capsule segment end at s = 0 (m); unused for a sphere
  Vec3 motion_m = Vec3::Zero();  ///< rigid translation at s = 1 (m)
  /// Point the tool's torque is reported about, at s = 0 (m): the sphere centre, the capsule's a, the
  /// catheter's tip (the foremost point of its rounded end).
  Vec3 tool_point_m = Vec3::Zero();
  bool catheter = false;  ///< built by make_catheter (a capsule whose a end is the tip)
  double length_m = 0.0;  ///< catheter: tip to shaft end (m)
  /// Radius of the node spheres the tool meets (m; 0: nodes are points). Contact keeps nodes this far
  /// outside the tool, so a tool thinner than about 2 node spacings cannot slip between nodes
  /// (docs/haptics.md); the price is a gap of this size between tool and wall.
  double node_radius_m = 0.0;
};

/// A catheter of outer `diameter_m` whose rounded tip's foremost point is `tip_m` and which points along
/// `direction` (any length > 0), rigid over `length_m` (tip plus the short shaft behind it). Throws
/// InputError if the diameter or length is not positive, the length is shorter than the diameter, or the
/// direction is zero.
RigidObstacle make_catheter(const std::string& name, const Vec3& tip_m, const Vec3& direction,
                            double diameter_m, double length_m);

/// The obstacle's contact geometry at load factor s (translated by s * motion_m; radius_m + node_radius_m).
/// A sphere is a capsule with a = b.
constraints::Capsule obstacle_at(const RigidObstacle& obstacle, double s);

/// The tool point at load factor s, m.
Vec3 tool_point_at(const RigidObstacle& obstacle, double s);

/// The obstacle placed by a device pose: the tool point moves to `position_m` and the obstacle is rotated
/// by `orientation`, which maps the tool frame (the tool points along its local -z, DevicePose) to the
/// scene. For a catheter, orientation * (0, 0, -1) is the direction the tip points; a sphere ignores the
/// orientation; a capsule keeps its rest shape relative to its tool point, with its rest pose taken as
/// the identity orientation.
constraints::Capsule obstacle_posed(const RigidObstacle& obstacle, const Vec3& position_m,
                                    const Eigen::Quaterniond& orientation);

/// The orientation that points the tool frame's -z along `direction` (for a catheter's rest pose).
Eigen::Quaterniond orientation_pointing(const Vec3& direction);

/// One-sided contact of a point with the geometry: C = distance - radius, n outward (points are nodes).
inline constraints::ContactConstraint obstacle_contact(const constraints::Capsule& geometry, const Vec3& p) {
  return constraints::capsule_contact(p, 0.0, geometry);
}

/// The load a tool exchanges with the tissue at one output point.
struct ObstacleLoad {
  Vec3 force_vector_n = Vec3::Zero();     ///< force the tool exerts on the tissue, N
  Vec3 torque_vector_n_m = Vec3::Zero();  ///< moment of that force about the tool point, N m
  int contacts = 0;                       ///< nodes in contact
};

}  // namespace vascsim
