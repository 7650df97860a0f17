#pragma once
// The rod's inertia in a backward-Euler step (docs/model/26-rod.md section 26.6), as an energy its static
// solver minimises with the rest: E_m = sum_i m_i / (2 h^2) |x_i - x_i^pred|^2, x^pred = x_n + h v_n (J).
// Minimising it with the elastic, contact and load energies is one implicit Euler step of length h; where a
// static equilibrium does not exist (a rod that slides down a wall faster than friction holds it) the step
// still has a solution. Lumped masses, rho A over each node's half edges; the frames' rotational inertia (rho
// I per length, 10^-7 of the translational for a wire) is left out.

#include "vascsim/rod/rod_potential.hpp"

namespace vascsim::rod {

class RodInertia final : public RodPotential {
 public:
  /// `linear_density_kg_per_m` (rho A, > 0) and the step `step_s` (> 0); starts at rest at the rod's
  /// configuration. Throws InputError for values that are not positive.
  RodInertia(const CosseratRod& rod, double linear_density_kg_per_m, double step_s);

  /// The prediction x_n + h v_n the next step is drawn towards (call before solving the step).
  void begin_step();
  /// The step's end: v_{n+1} = (x - x_n) / h, x_{n+1} = x.
  void end_step(const CosseratRod& rod);

  double energy(const CosseratRod& rod) const override;
  void add_gradient(const CosseratRod& rod, Eigen::VectorXd& g) const override;
  void add_hessian(const CosseratRod& rod, std::vector<Eigen::Triplet<double>>& t) const override;

  const std::vector<double>& masses() const { return m_; }  ///< kg per node
  const Vec3Array& velocities() const { return v_; }        ///< m/s per node

 private:
  double h_ = 0.0;
  std::vector<double> m_;
  Vec3Array x_n_, v_, pred_;
};

}  // namespace vascsim::rod
