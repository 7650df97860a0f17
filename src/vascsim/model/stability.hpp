#pragma once
// Explicit stability limit (docs/model/12-equation-of-motion.md): dt_crit = 2 / omega_max with omega_max^2 =
// lambda_max(M^-1 K) of the free degrees of freedom, and the CFL-type rule dt <= C * Delta_min / c_p.

#include "vascsim/model/problem.hpp"

namespace vascsim {

/// Largest angular frequency omega_max (rad/s) of the free nodes, linearised at configuration x, by
/// power iteration on M^-1/2 H M^-1/2 (each iteration one analytic Hessian-vector product). Stops after
/// `max_iterations` or when the Rayleigh quotient changes by less than `rel_tol`. Deterministic (seeded).
double max_angular_frequency(const Problem& problem, const Vec3Array& x, int max_iterations,
                             double rel_tol = 1e-6, int* iterations_used = nullptr);

/// The rule-of-thumb limit C * Delta_min / c_p (s): C = 0.4 in sound mode, 0.2 with the literal strain
/// (whose 4x energy doubles the wave speed).
double cfl_time_step(const PointPrimitiveEnergy& energy, double coefficient = 0.4);

}  // namespace vascsim
