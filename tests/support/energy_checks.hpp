#pragma once
// Checks shared by the energy tests: the large deformation of the T4/T5 checks, and forces against central
// differences of the energy (docs/validation.md T5, docs/validation.md).

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

#include "vascsim/core/types.hpp"

#include "support/test_support.hpp"

namespace vascsim::test {

// docs/validation.md T4/T5 deformation: x = R (I + 0.1 rand) X plus 0.05 Delta noise (rand, noise uniform in [-1, 1]).
inline Vec3Array large_deformation(const Vec3Array& X, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  Mat3 B;
  for (int k = 0; k < 9; ++k) B(k) = uni(rng);
  const Mat3 R = Eigen::AngleAxisd(2.0, Vec3(1.0, 2.0, -0.5).normalized()).toRotationMatrix();
  const Mat3 A = R * (Mat3::Identity() + 0.1 * B);
  Vec3Array x(X.size());
  for (std::size_t i = 0; i < X.size(); ++i)
    x[i] = A * X[i] + 0.05 * kDelta * Vec3(uni(rng), uni(rng), uni(rng));
  return x;
}

inline double max_norm(const Vec3Array& a) {
  double m = 0.0;
  for (const Vec3& v : a) m = std::max(m, v.norm());
  return m;
}

// max over 30 random DOFs of |f + dU/dx| / max|f|, with dU/dx by central differences of step 1e-7 Delta.
inline double fd_force_error(const std::function<double(const Vec3Array&)>& U, const Vec3Array& f, Vec3Array x) {
  const SingleThreaded serial;  // a few hundred energies of a few hundred nodes: one thread
  std::mt19937_64 rng(99);
  std::uniform_int_distribution<std::size_t> node(0, x.size() - 1);
  std::uniform_int_distribution<int> comp(0, 2);
  const double step = 1e-7 * kDelta;
  double f_max = 0.0;
  for (const Vec3& v : f) f_max = std::max(f_max, v.cwiseAbs().maxCoeff());
  double err = 0.0;
  for (int s = 0; s < 30; ++s) {
    const std::size_t i = node(rng);
    const int c = comp(rng);
    const double x0 = x[i][c];
    x[i][c] = x0 + step;
    const double up = U(x);
    x[i][c] = x0 - step;
    const double down = U(x);
    x[i][c] = x0;
    err = std::max(err, std::abs(f[i][c] + (up - down) / (2.0 * step)));
  }
  return err / f_max;
}

}  // namespace vascsim::test
