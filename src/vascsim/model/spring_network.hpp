#pragma once
// Damped springs between node pairs, the force law of the mass-spring baselines (docs/model/25-baselines.md):
//   f_a = -[k(l) (l - l0) + c dl/dt] n,  f_b = -f_a,  n = (x_a - x_b)/l,  l = |x_a - x_b|,
//   k(l) = k0 (1 + a ((l - l0)/l0)^2)   (a = 0: the linear spring; a > 0: the stiffening Kelvin-Voigt
//   element),
// with the stiffness rules that tie k0 to the material: Van Gelder's for a triangulated shell of thickness t,
// k_e = E t sum_{T contains e} A_T / |e|^2 (A. Van Gelder, "Approximate simulation of elastic membranes by
// triangulated spring meshes", J. Graphics Tools 3(2), 1998), and its volume analogue for a tetrahedral
// network, k_e = E sum_{T contains e} V_T / |e|^2. Both give an isotropic network exactly the Young's modulus
// E (docs/model/25-baselines.md §25.1 derives it), with the network's own Poisson ratio (1/3 in a sheet, 1/4
// in a solid).

#include <vector>

#include "vascsim/geometry/boundary.hpp"

namespace vascsim {

struct SpringNetwork {
  std::vector<Edge> ends;         ///< (a, b) node pairs
  std::vector<double> rest_m;     ///< l0, m
  std::vector<double> stiffness;  ///< k0, N/m
  std::vector<double> damping;    ///< c, N s/m
  double nonlinearity = 0.0;      ///< a (dimensionless); 0: linear springs

  std::size_t size() const { return ends.size(); }
  /// Appends a spring at rest between a and b (rest length from X).
  void add(const Vec3Array& X, Index a, Index b, double k, double c);
  /// Adds every spring's force at positions x and velocities v into f (sized like x).
  void add_forces(const Vec3Array& x, const Vec3Array& v, Vec3Array& f) const;
  /// Gershgorin bounds of the undamped and damped rates over the nodes with mass > 0:
  /// omega^2 <= max_i 2 sum_j k_ij / m_i (1/s^2) and gamma <= max_i 2 sum_j c_ij / m_i (1/s), the linear
  /// stiffness taken at the largest strain `strain` the nonlinear term is allowed (k0 (1 + a strain^2)).
  void rate_bounds(const std::vector<double>& mass, double strain, double& omega2, double& gamma) const;
  /// Adds the Gershgorin row sums of the springs' stiffness (2 k per spring end, N/m) and damping (2 c, N
  /// s/m) at strain `strain` to k_rows and c_rows (sized like the nodes).
  void add_row_sums(double strain, std::vector<double>& k_rows, std::vector<double>& c_rows) const;
};

/// max_i k_rows_i / m_i (omega^2, 1/s^2) and max_i c_rows_i / m_i (gamma, 1/s) over the nodes with mass > 0.
void max_rates(const std::vector<double>& mass, const std::vector<double>& k_rows,
               const std::vector<double>& c_rows, double& omega2, double& gamma);

/// The stable step of symplectic Euler for rates omega (1/s) and gamma (1/s): 2 / (omega + gamma) satisfies
/// dt^2 omega^2 + 2 dt gamma <= 4 (the Jury condition of one damped mode; it reduces to 2/omega and 2/gamma),
/// times `safety`.
double symplectic_euler_step(double omega2, double gamma, double safety);

/// The tetrahedral network of `tets` over X: one spring per distinct tet edge, k = E sum V_T / |e|^2 (see the
/// file comment), damping c = tau k (Kelvin-Voigt, relaxation time tau in s).
SpringNetwork tet_edge_springs(const Vec3Array& X, const std::vector<Tet>& tets, double youngs_pa,
                               double tau_s);

}  // namespace vascsim
