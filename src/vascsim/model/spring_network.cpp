#include "vascsim/model/spring_network.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace vascsim {

void SpringNetwork::add(const Vec3Array& X, Index a, Index b, double k, double c) {
  ends.push_back({a, b});
  rest_m.push_back((X[a] - X[b]).norm());
  stiffness.push_back(k);
  damping.push_back(c);
}

void SpringNetwork::add_forces(const Vec3Array& x, const Vec3Array& v, Vec3Array& f) const {
  for (std::size_t e = 0; e < ends.size(); ++e) {
    const auto [a, b] = ends[e];
    const Vec3 d = x[a] - x[b];
    const double l = d.norm();
    if (!(l > 0.0)) continue;
    const Vec3 n = d / l;
    const double strain = (l - rest_m[e]) / rest_m[e];
    const double k = stiffness[e] * (1.0 + nonlinearity * strain * strain);
    const double f_mag = k * (l - rest_m[e]) + damping[e] * n.dot(v[a] - v[b]);
    f[a] -= f_mag * n;
    f[b] += f_mag * n;
  }
}

void SpringNetwork::add_row_sums(double strain, std::vector<double>& k_rows,
                                 std::vector<double>& c_rows) const {
  // The tangent of the nonlinear spring at strain s is k0 (1 + 3 a s^2); the bound uses it.
  const double factor = 1.0 + 3.0 * nonlinearity * strain * strain;
  for (std::size_t e = 0; e < ends.size(); ++e)
    for (Index i : ends[e]) {
      k_rows[i] += 2.0 * stiffness[e] * factor;
      c_rows[i] += 2.0 * damping[e];
    }
}

void max_rates(const std::vector<double>& mass, const std::vector<double>& k_rows,
               const std::vector<double>& c_rows, double& omega2, double& gamma) {
  omega2 = 0.0;
  gamma = 0.0;
  for (std::size_t i = 0; i < mass.size(); ++i) {
    if (!(mass[i] > 0.0)) continue;
    omega2 = std::max(omega2, k_rows[i] / mass[i]);
    gamma = std::max(gamma, c_rows[i] / mass[i]);
  }
}

void SpringNetwork::rate_bounds(const std::vector<double>& mass, double strain, double& omega2,
                                double& gamma) const {
  std::vector<double> k_rows(mass.size(), 0.0), c_rows(mass.size(), 0.0);
  add_row_sums(strain, k_rows, c_rows);
  max_rates(mass, k_rows, c_rows, omega2, gamma);
}

double symplectic_euler_step(double omega2, double gamma, double safety) {
  const double rate = std::sqrt(omega2) + gamma;
  return rate > 0.0 ? safety * 2.0 / rate : 1.0;
}

SpringNetwork tet_edge_springs(const Vec3Array& X, const std::vector<Tet>& tets, double youngs_pa,
                               double tau_s) {
  std::map<Edge, double> volume;  // sum of the volumes of the tets around each edge, m^3
  for (const Tet& t : tets) {
    const double V = std::abs(signed_volume(X[t[0]], X[t[1]], X[t[2]], X[t[3]]));
    for (int p = 0; p < 4; ++p)
      for (int q = p + 1; q < 4; ++q) volume[{std::min(t[p], t[q]), std::max(t[p], t[q])}] += V;
  }
  SpringNetwork net;
  for (const auto& [e, V] : volume) {
    const double k = youngs_pa * V / (X[e[0]] - X[e[1]]).squaredNorm();
    net.add(X, e[0], e[1], k, tau_s * k);
  }
  return net;
}

}  // namespace vascsim
