#pragma once
// Coulomb friction between the rod and the lumen's wall (docs/model/26-rod.md section 26.6), lagged over a
// step as in incremental potential contact (Li et al. 2020): each node in contact keeps, from the step's
// start, its position a_i, its contact's normal n_i and normal force lambda_i, and the step adds the
// dissipation potential
//     D = sum_i mu lambda_i f(|u_i|),   u_i = (I - n_i n_i^T)(x_i - a_i)   (the node's slip in the wall's
//     plane)
// with f(y) = y^2 / 2e below the slip e and y - e/2 above: a force of mu lambda_i against the slip once it
// exceeds e, a stiff spring below (static friction; a node that sticks creeps by at most e per step).
// Hydrophilic coatings have mu of about 0.02-0.1.

#include "vascsim/rod/lumen_contact.hpp"

namespace vascsim::rod {

class LumenFriction final : public RodPotential {
 public:
  /// Friction coefficient `mu` (>= 0) and the slip `slip_m` (> 0) below which a node sticks. Throws
  /// InputError otherwise.
  LumenFriction(double mu, double slip_m);
  /// Takes the step's anchors from `rod` and the normal forces of `contact` at its configuration.
  void begin_step(const CosseratRod& rod, const LumenContact& contact, const Lumen& lumen);

  double energy(const CosseratRod& rod) const override;
  void add_gradient(const CosseratRod& rod, Eigen::VectorXd& g) const override;
  void add_hessian(const CosseratRod& rod, std::vector<Eigen::Triplet<double>>& t) const override;

 private:
  double mu_ = 0.0, e_ = 0.0;
  Vec3Array anchor_, normal_;
  std::vector<double> normal_force_;  // N
};

}  // namespace vascsim::rod
