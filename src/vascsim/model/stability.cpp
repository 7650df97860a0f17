#include "vascsim/model/stability.hpp"

#include <cmath>
#include <random>

namespace vascsim {

double max_angular_frequency(const Problem& problem, const Vec3Array& x, int max_iterations, double rel_tol,
                             int* iterations_used) {
  const auto& disc = problem.discretization();
  const auto& m = disc.masses();
  const auto& fixed = problem.constrained();
  const Index n = disc.num_nodes();
  std::mt19937_64 rng(12345);
  std::normal_distribution<double> normal;
  Vec3Array z(n), y(n), Hy;
  for (Index i = 0; i < n; ++i) z[i] = fixed[i] ? Vec3::Zero() : Vec3(normal(rng), normal(rng), normal(rng));
  auto normalise = [&](Vec3Array& a) {
    double s = 0.0;
    for (const auto& v : a) s += v.squaredNorm();
    s = std::sqrt(s);
    for (auto& v : a) v /= s;
  };
  normalise(z);
  double rq = 0.0;
  int it = 0;
  for (; it < max_iterations; ++it) {
    for (Index i = 0; i < n; ++i) y[i] = z[i] / std::sqrt(m[i]);
    problem.energy().hessian_product(x, y, Hy);
    double next = 0.0;
    for (Index i = 0; i < n; ++i) {
      z[i] = fixed[i] ? Vec3::Zero() : Vec3(Hy[i] / std::sqrt(m[i]));
      next += y[i].dot(Hy[i]);  // z_old^T (M^-1/2 H M^-1/2) z_old, with |z_old| = 1
    }
    normalise(z);
    const bool done = it > 0 && std::abs(next - rq) <= rel_tol * std::abs(next);
    rq = next;
    if (done) break;
  }
  if (iterations_used) *iterations_used = it;
  return std::sqrt(std::max(rq, 0.0));
}

double cfl_time_step(const PointPrimitiveEnergy& energy, double coefficient) {
  const auto& disc = energy.discretization();
  const double c = coefficient * (energy.options().strain == StrainMeasure::MuellerNoHalf ? 0.5 : 1.0);
  return c * disc.min_spacing() / disc.material().p_wave_speed();
}

}  // namespace vascsim
