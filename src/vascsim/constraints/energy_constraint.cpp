#include "vascsim/constraints/energy_constraint.hpp"

#include <cmath>

#include <stdexcept>

namespace vascsim::constraints {

namespace {
double total_mass(const TetMasses& m) {
  return m[0] + m[1] + m[2] + m[3];
}

Vec3 unit_or_zero(const Vec3& v) {
  const double n = v.norm();
  return n > 0.0 ? Vec3(v / n) : Vec3::Zero();
}
}  // namespace

Vec3 mass_weighted_barycentre(const TetPositions& x, const TetMasses& m) {
  return (m[0] * x[0] + m[1] * x[1] + m[2] * x[2] + m[3] * x[3]) / total_mass(m);
}

std::array<double, 4> barycentre_rest_distances(const TetPositions& X, const TetMasses& m) {
  const Vec3 X0 = mass_weighted_barycentre(X, m);
  return {(X[0] - X0).norm(), (X[1] - X0).norm(), (X[2] - X0).norm(), (X[3] - X0).norm()};
}

ScalarConstraint<4> barycentre_spring_constraint(const TetPositions& x, const TetMasses& m, int a,
                                                 double rest_distance) {
  if (a < 0 || a > 3)
    throw std::invalid_argument("barycentre_spring_constraint: vertex index a must be 0..3");
  const double M = total_mass(m);
  const Vec3 r = x[a] - mass_weighted_barycentre(x, m);
  const Vec3 n = unit_or_zero(r);
  ScalarConstraint<4> c;
  c.value = r.norm() - rest_distance;
  for (int b = 0; b < 4; ++b) c.grad[b] = ((b == a ? 1.0 : 0.0) - m[b] / M) * n;
  return c;
}

double barycentre_spring_denominator(const TetMasses& m, int a) {
  return 1.0 / m[a] - 1.0 / total_mass(m);
}

double barycentre_spring_stiffness(double bulk_modulus_pa, double rest_volume_m3,
                                   const std::array<double, 4>& rest_distances) {
  double sum_d2 = 0.0;
  for (double d : rest_distances) sum_d2 += d * d;
  return 9.0 * bulk_modulus_pa * rest_volume_m3 / sum_d2;
}

BarycentreSprings barycentre_springs(const TetPositions& X, const TetMasses& m, double bulk_modulus_pa) {
  BarycentreSprings s;
  s.rest_distances = barycentre_rest_distances(X, m);
  const double volume = std::abs((X[1] - X[0]).dot((X[2] - X[0]).cross(X[3] - X[0]))) / 6.0;
  s.stiffness = barycentre_spring_stiffness(bulk_modulus_pa, volume, s.rest_distances);
  return s;
}

ScalarConstraint<4> literal_energy_constraint(const TetPositions& x, const TetMasses& m,
                                              const std::array<double, 4>& k,
                                              const std::array<double, 4>& rest_distances) {
  const Vec3 x0 = mass_weighted_barycentre(x, m);
  ScalarConstraint<4> c;
  c.value = 0.0;
  for (int b = 0; b < 4; ++b) {
    const Vec3 r = x[b] - x0;
    const double delta = r.norm() - rest_distances[b];
    c.value += 0.5 * k[b] * delta * delta;  // Eq. 18
    c.grad[b] = unit_or_zero(r);            // Eqs. 20-23 as printed
  }
  return c;
}

std::vector<BarycentreSprings> barycentre_springs_of_mesh(const Vec3Array& X,
                                                          const std::vector<std::array<Index, 4>>& tets,
                                                          const std::vector<double>& masses,
                                                          double bulk_modulus_pa) {
  std::vector<BarycentreSprings> out(tets.size());
  for (std::size_t t = 0; t < tets.size(); ++t) {
    TetPositions x;
    TetMasses m;
    for (int a = 0; a < 4; ++a) {
      x[a] = X[static_cast<std::size_t>(tets[t][a])];
      m[a] = masses[static_cast<std::size_t>(tets[t][a])];
    }
    out[t] = barycentre_springs(x, m, bulk_modulus_pa);
  }
  return out;
}

}  // namespace vascsim::constraints
