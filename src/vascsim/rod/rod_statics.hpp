#pragma once
// Static equilibrium of a Cosserat rod under dead loads (docs/model/26-rod.md): minimises the potential
// Pi = E(x, q) - sum_i f_i . x_i over the free generalised coordinates by Newton's method on the rod's exact
// Hessian (a sparse LDL^T factor: the rod's coordinates couple only neighbouring edges, so a factor costs a
// few times the rod's size), with a shift that keeps each step a descent direction where the Hessian is
// indefinite (past a buckling load) and a backtracking line search on Pi. The load is applied in equal steps.

#include <vector>

#include "vascsim/rod/cosserat_rod.hpp"
#include "vascsim/rod/rod_potential.hpp"

namespace vascsim::rod {

struct RodStaticsOptions {
  int load_steps = 1;               ///< equal increments of the forces
  int max_newton_iterations = 100;  ///< per load step
  /// Converged when the free gradient of Pi is at most this times the load's scale (the largest of the
  /// forces, the reactions on the held coordinates and the forces of the rod's elasticity and of the other
  /// energies on the free ones; the rotational components divided by the
  /// rod's length to make them forces), plus the round-off of the edges' stretch forces (EA 16 eps |x| / l).
  double rel_tolerance = 1e-10;
};

struct RodStaticsReport {
  bool converged = false;
  int newton_iterations = 0;  ///< over all load steps
  double relative_residual = 0.0;
};

/// Solves for the equilibrium of `rod` from its current configuration. `held`: one flag per generalised
/// coordinate (CosseratRod::position_dof, rotation_dof), true for a coordinate kept where it is; `forces`: a
/// dead force per node (N; empty for none); `potentials`: energies added to the rod's (its contacts). Throws
/// std::invalid_argument for sizes that do not match the rod.
RodStaticsReport solve_rod_statics(CosseratRod& rod, const std::vector<char>& held, const Vec3Array& forces,
                                   const RodStaticsOptions& options = {},
                                   const std::vector<const RodPotential*>& potentials = {});

/// Whether the Hessian of `rod` on its free coordinates (held as above) is positive definite: the equilibrium
/// is stable (the count of negative pivots of its LDL^T factor, Sylvester's law of inertia).
bool rod_is_stable(const CosseratRod& rod, const std::vector<char>& held,
                   const std::vector<const RodPotential*>& potentials = {});

}  // namespace vascsim::rod
