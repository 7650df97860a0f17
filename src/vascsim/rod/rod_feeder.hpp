#pragma once
// Feeding a rod through an access port (docs/model/26-rod.md section 26.5): the two motions a trainee's hands
// make at the access site, insertion along the port's axis and rotation about it. The rod keeps its length;
// the part behind the port (outside the body) is held on the port's axis, straight, turned by the twist, and
// the part past the port is free (and meets the lumen). A change of insertion slides every free node along
// the rod's current curve, the tip going on along its last edge: the prediction the next equilibrium starts
// from.

#include <vector>

#include "vascsim/rod/cosserat_rod.hpp"

namespace vascsim::rod {

struct AccessPort {
  Vec3 position_m = Vec3::Zero();  ///< where the rod enters the lumen
  Vec3 axis = Vec3::UnitZ();       ///< into the lumen (normalised here)
};

class RodFeeder {
 public:
  /// Places `rod` (which must outlive this) with `inserted_m` of its length past the port, its shaft on the
  /// port's axis and its rest shape otherwise. The rod's rest shape must be straight over the part behind the
  /// port (the shaft). Throws InputError for an insertion outside (0, length less the first edge: one edge
  /// stays behind the port and holds the rod's turn) or a port axis of zero length.
  RodFeeder(CosseratRod& rod, const AccessPort& port, double inserted_m);

  /// Feeds to `inserted_m` past the port (m) and turns the proximal end to `twist_rad` about the port's axis
  /// (from the placement). Throws InputError for an insertion outside that range.
  void drive(double inserted_m, double twist_rad);

  double inserted_m() const { return inserted_; }
  double twist_rad() const { return twist_; }
  /// Per generalised coordinate: held by the port (the positions of nodes at or behind it, the frames of
  /// edges wholly behind it).
  const std::vector<char>& held() const { return held_; }
  /// Per node: at or behind the port (outside the body: no contact with the lumen).
  const std::vector<char>& outside() const { return outside_; }

 private:
  void hold();  // places the nodes and edges behind the port and flags them

  CosseratRod& rod_;
  AccessPort port_;
  Quaternion shaft_;       // the shaft's frame at zero twist
  std::vector<double> s_;  // each node's arc length from the proximal end at rest, m
  double inserted_ = 0.0, twist_ = 0.0;
  std::vector<char> held_, outside_;
};

}  // namespace vascsim::rod
