#pragma once
// Where each of a problem's tools is for an equilibrium solve: moved by the load factor (its motion_m), or,
// once a device has posed it (DeviceDrivenModel::set_tool_pose), at that pose. Shared by the models that
// solve for equilibrium with tools (quasi_static, implicit).
//
// A real-time model may follow a device pose in bounded steps (advance): the pose it solves for moves towards
// the device's by at most a set distance per frame, so a frame never starts from a tool that jumped far into
// the tissue (a slow frame would otherwise make the next jump longer, and the next frame slower still). The
// pose the model used is reported with its force, so the haptic thread extrapolates from where the model was.

#include <Eigen/Geometry>
#include <limits>
#include <vector>

#include "vascsim/model/problem.hpp"

namespace vascsim {

class ToolPlacement {
 public:
  explicit ToolPlacement(const std::vector<RigidObstacle>& tools)
      : tools_(tools),
        posed_(tools.size(), 0),
        geometry_(tools.size()),
        target_(tools.size()),
        used_(tools.size()) {}

  /// Poses tool o: its tool point at position_m, rotated by orientation (obstacle_posed). From now on it
  /// ignores the load factor. The first pose is taken at once; later ones through advance() when a model
  /// bounds the step (immediately otherwise). Throws std::out_of_range for a bad o.
  void pose(std::size_t o, const Vec3& position_m, const Eigen::Quaterniond& orientation) {
    target_.at(o) = {position_m, orientation.normalized()};
    if (!posed_[o] || !bounded_) place(o, target_[o]);
    posed_[o] = 1;
  }
  /// Bounded following (a real-time model): poses move towards their targets only in advance().
  void set_bounded(bool bounded) { bounded_ = bounded; }
  /// Moves posed tool o towards its target by at most max_step_m (the orientation turns by the same fraction
  /// of the way; infinity: to the target). Returns the distance still to go, m.
  double advance(std::size_t o, double max_step_m) {
    if (!posed_.at(o)) return 0.0;
    const Vec3 to_go = target_[o].position - used_[o].position;
    const double d = to_go.norm();
    if (d <= max_step_m) {
      place(o, target_[o]);
      return 0.0;
    }
    const double f = max_step_m / d;
    place(o, {used_[o].position + f * to_go, used_[o].orientation.slerp(f, target_[o].orientation)});
    return d - max_step_m;
  }
  /// Posed tool o's contact geometry a fraction f (in [0, 1]) of the way from where the model has it to the
  /// device's pose.
  constraints::Capsule geometry_towards_target(std::size_t o, double f) const {
    return obstacle_posed(tools_[o], used_[o].position + f * (target_[o].position - used_[o].position),
                          used_[o].orientation.slerp(f, target_[o].orientation));
  }
  /// How far posed tool o is from the device's pose, m (0 for a tool no device posed).
  double distance_to_target(std::size_t o) const {
    return posed_[o] ? (target_[o].position - used_[o].position).norm() : 0.0;
  }
  /// Tool o's contact geometry at load factor s.
  constraints::Capsule geometry(std::size_t o, double s) const {
    return posed_[o] ? geometry_[o] : obstacle_at(tools_[o], s);
  }
  /// Every tool's point (the catheter's tip; the point torques are reported about) at load factor s, m: where
  /// the model has it, which for a bounded model may trail the device's pose.
  std::vector<Vec3> points(double s) const {
    std::vector<Vec3> p;
    for (std::size_t o = 0; o < tools_.size(); ++o)
      p.push_back(posed_[o] ? used_[o].position : tool_point_at(tools_[o], s));
    return p;
  }
  /// Every tool's target (the device's pose for a posed tool, else its point at load factor s), m.
  std::vector<Vec3> target_points(double s) const {
    std::vector<Vec3> p;
    for (std::size_t o = 0; o < tools_.size(); ++o)
      p.push_back(posed_[o] ? target_[o].position : tool_point_at(tools_[o], s));
    return p;
  }
  std::size_t size() const { return tools_.size(); }

  struct Pose {
    Vec3 position = Vec3::Zero();
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  };
  /// Where the model has every tool, to go back to with restore().
  std::vector<Pose> placed() const { return used_; }
  /// Every tool back where placed() found it (the device's poses stay the targets).
  void restore(const std::vector<Pose>& placed) {
    for (std::size_t o = 0; o < tools_.size(); ++o) place(o, placed.at(o));
  }

 private:
  void place(std::size_t o, const Pose& p) {
    used_[o] = p;
    geometry_[o] = obstacle_posed(tools_[o], p.position, p.orientation);
  }
  const std::vector<RigidObstacle>& tools_;
  std::vector<char> posed_;
  std::vector<constraints::Capsule> geometry_;
  std::vector<Pose> target_, used_;
  bool bounded_ = false;
};

}  // namespace vascsim
