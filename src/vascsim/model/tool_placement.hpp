#pragma once
// Where each of a problem's tools is for an equilibrium solve: moved by the load factor (its motion_m), or,
// once a device has posed it (DeviceDrivenModel::set_tool_pose), at that pose. Shared by the models that
// solve for equilibrium with tools (quasi_static, implicit).

#include <vector>

#include "vascsim/model/problem.hpp"

namespace vascsim {

class ToolPlacement {
 public:
  explicit ToolPlacement(const std::vector<RigidObstacle>& tools)
      : tools_(tools), posed_(tools.size(), 0), geometry_(tools.size()), point_(tools.size(), Vec3::Zero()) {}
  /// Poses tool o: its tool point at position_m, rotated by orientation (obstacle_posed). From now on it
  /// ignores the load factor. Throws std::out_of_range for a bad o.
  void pose(std::size_t o, const Vec3& position_m, const Eigen::Quaterniond& orientation) {
    geometry_.at(o) = obstacle_posed(tools_.at(o), position_m, orientation);
    point_[o] = position_m;
    posed_[o] = 1;
  }
  /// Tool o's contact geometry at load factor s.
  constraints::Capsule geometry(std::size_t o, double s) const {
    return posed_[o] ? geometry_[o] : obstacle_at(tools_[o], s);
  }
  /// Every tool's point (the catheter's tip; the point torques are reported about) at load factor s, m.
  std::vector<Vec3> points(double s) const {
    std::vector<Vec3> p;
    for (std::size_t o = 0; o < tools_.size(); ++o) p.push_back(posed_[o] ? point_[o] : tool_point_at(tools_[o], s));
    return p;
  }
  std::size_t size() const { return tools_.size(); }

 private:
  const std::vector<RigidObstacle>& tools_;
  std::vector<char> posed_;
  std::vector<constraints::Capsule> geometry_;
  std::vector<Vec3> point_;
};

}  // namespace vascsim
