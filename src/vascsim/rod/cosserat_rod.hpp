#pragma once
// A Cosserat rod (the Simo-Reissner geometrically exact beam) discretised in edges, for flexible instruments:
// stretch, shear, bending and twist, large rotations, any natural shape (docs/model/26-rod.md).
//
// Unknowns: the node positions x_i (i = 0..N) and one material frame q_j per edge (a unit quaternion; d3
// along the rod at rest). Energy, J:
//     E = sum_j 1/2 l_j Gamma_j^T C_s Gamma_j + sum_b 1/2 lbar_b (Omega_b - Omega^0_b)^T C_b (Omega_b -
//     Omega^0_b)
// - per edge j, the shear and stretch strain Gamma_j = R_j^T (x_{j+1} - x_j) / l_j - e3 (C_s = diag(kGA, kGA,
// EA));
// - per bend point b between two consecutive frames a, c, the Darboux vector Omega_b = (2 / lbar_b) Im(q_a^*
// q_c)
//   (curvature about d1, d2 and twist about d3, in a's frame; 2 sin(theta/2) / lbar for a relative rotation
//   theta, theta / lbar to O(theta^3)) against its rest value (C_b = diag(EI, EI, GJ)), lbar_b the mean
//   length of the two edges.
// A clamp holds a frame at an end node: a bend point between it and the end edge, over half the edge, so the
// clamped frame sits at the end of the rod, not at the middle of its first edge (the rod's compliance over
// that half edge is kept: second-order accuracy in the edge length).
//
// Derivatives are taken in the rod's generalised coordinates: the positions, and per edge a rotation
// increment psi_j in the edge's own frame (q_j <- q_j exp(psi_j)), so the gradient's rotational part is the
// torque on the edge about its own axes (N m) and a Newton step needs no constraint on the quaternions.
// Gradient and Hessian are exact (tests/rod/test_cosserat_rod.cpp compares them with finite differences).

#include <Eigen/SparseCore>
#include <vector>

#include "vascsim/rod/rod_section.hpp"
#include "vascsim/rod/rod_shape.hpp"

namespace vascsim::rod {

class CosseratRod {
 public:
  /// A rod at rest in `rest` (at least one edge) with the stiffness `k`. Throws InputError for a stiffness
  /// that is not positive.
  CosseratRod(const RodRestShape& rest, const RodStiffness& k);

  Index num_nodes() const { return static_cast<Index>(x_.size()); }
  Index num_edges() const { return static_cast<Index>(q_.size()); }
  /// Generalised coordinates: 3 per node (position, m) then 3 per edge (rotation increment, rad).
  Index num_dofs() const { return 3 * (num_nodes() + num_edges()); }
  static Index position_dof(Index node) { return 3 * node; }
  Index rotation_dof(Index edge) const { return 3 * (num_nodes() + edge); }

  const Vec3Array& positions() const { return x_; }
  const std::vector<Quaternion>& frames() const { return q_; }
  const RodRestShape& rest_shape() const { return rest_; }
  const RodStiffness& stiffness() const { return k_; }
  /// Replaces the configuration (positions in m, unit frames); sizes must match.
  void set_configuration(const Vec3Array& x, const std::vector<Quaternion>& q);

  /// Holds a frame at node 0 (`frame`: the frame held there; at rest, the first edge's rest frame leaves the
  /// rod unstressed). The rod's own degrees of freedom stay free: a solver fixes node 0's position itself.
  void clamp_start(const Quaternion& frame);
  /// The same at the last node.
  void clamp_end(const Quaternion& frame);
  /// Turns a clamp already set to `frame` (the rest of the rod keeps its configuration).
  void move_start_clamp(const Quaternion& frame);
  void move_end_clamp(const Quaternion& frame);

  /// Elastic energy, J.
  double energy() const;
  /// dE/d(coordinates): N on the positions, N m on the rotations (about the edge's own axes).
  Eigen::VectorXd gradient() const;
  /// d^2E/d(coordinates)^2 at the current configuration, symmetric (both triangles stored).
  Eigen::SparseMatrix<double> hessian() const;
  /// Moves by `d` in the generalised coordinates: x_i += d_i, q_j <- q_j exp(psi_j) (exact exponential).
  void apply_increment(const Eigen::VectorXd& d, double scale = 1.0);

  /// The bend points: interior node i (1..N-1) is point i - 1; then the start clamp's, then the end clamp's.
  Index num_bend_points() const { return static_cast<Index>(bends_.size()); }
  /// The internal moment C_b (Omega_b - Omega^0_b) at bend point b, in the frame of the edge before it (the
  /// clamp's frame for the start clamp), N m: bending about d1, d2 and the twisting moment about d3.
  Vec3 moment(Index bend_point) const;
  /// The internal force C_s Gamma_j of edge j in its own frame, N: shear along d1, d2, tension along d3.
  Vec3 edge_force(Index edge) const;
  double length() const;  ///< the rest length, sum of the edges' rest lengths, m

 private:
  struct Bend {
    Index a = -1, c = -1;  // the frames before and after (-1: the clamp's)
    bool start_clamp = false, end_clamp = false;
    double lbar = 0.0;
    Vec3 rest_darboux = Vec3::Zero();
  };
  Quaternion frame_a(const Bend& b) const;
  Quaternion frame_c(const Bend& b) const;
  Vec3 darboux(const Bend& b) const;

  RodRestShape rest_;
  RodStiffness k_;
  Vec3Array x_;
  std::vector<Quaternion> q_;
  std::vector<double> l_;  // rest edge lengths, m
  std::vector<Bend> bends_;
  Quaternion start_clamp_ = Quaternion::Identity(), end_clamp_ = Quaternion::Identity();
};

}  // namespace vascsim::rod
