#pragma once
// An energy a rod feels beyond its own elasticity (its contact with a lumen, docs/model/26-rod.md): what the
// rod's static solver adds to the rod's energy, gradient and Hessian. Functions of the rod's configuration,
// in its generalised coordinates (CosseratRod::position_dof, rotation_dof).

#include <Eigen/SparseCore>
#include <vector>

#include "vascsim/rod/cosserat_rod.hpp"

namespace vascsim::rod {

class RodPotential {
 public:
  virtual ~RodPotential() = default;
  virtual double energy(const CosseratRod& rod) const = 0;  ///< J
  /// Adds dE/d(coordinates) to `g` (size rod.num_dofs()).
  virtual void add_gradient(const CosseratRod& rod, Eigen::VectorXd& g) const = 0;
  /// Adds a positive semidefinite approximation of (or exactly) d^2E/d(coordinates)^2.
  virtual void add_hessian(const CosseratRod& rod, std::vector<Eigen::Triplet<double>>& t) const = 0;
};

}  // namespace vascsim::rod
