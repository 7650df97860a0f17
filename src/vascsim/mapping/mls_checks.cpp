#include "vascsim/mapping/mls_checks.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

namespace vascsim {

namespace {

Mat3 random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  return q.normalized().toRotationMatrix();
}

// Maps x = A X + t through the map (double and float32); raises err / err_f32 to the worst error
// against A S + t, in units of delta.
void field_error(const MlsMap& map, const Vec3Array& X, const Mat3& A, const Vec3& t, double delta,
                 double& err, double& err_f32, double& max_u) {
  Vec3Array x(X.size());
  std::vector<Eigen::Vector3f> u32(X.size());
  for (std::size_t i = 0; i < X.size(); ++i) {
    x[i] = A * X[i] + t;
    u32[i] = (x[i] - X[i]).cast<float>();
    max_u = std::max(max_u, (x[i] - X[i]).norm());
  }
  Vec3Array xs;
  std::vector<Eigen::Vector3f> xs32;
  map.map_positions(x, xs);
  map.map_displacements_f32(u32, xs32);
  const Vec3Array& S = map.rest_surface();
  for (std::size_t v = 0; v < S.size(); ++v) {
    const Vec3 exact = A * S[v] + t;
    err = std::max(err, (xs[v] - exact).norm() / delta);
    err_f32 = std::max(err_f32, (xs32[v].cast<double>() - exact).norm() / delta);
  }
}

}  // namespace

bool MlsT11::passes() const {
  return unity <= 1e-12 && linear <= 1e-10 && affine <= 1e-10 && rigid90 <= 1e-10 && rigid_rand <= 1e-10 &&
         (f32 <= 1e-5 || f32_over_input_rounding <= 8.0) && max_cond <= 1e3 && min_support >= 8;
}

MlsT11 measure_mls_t11(const MlsMap& map, const Vec3Array& X, double delta, std::uint64_t seed) {
  MlsT11 m;
  const auto& rs = map.row_start();
  const Vec3Array& S = map.rest_surface();
  m.min_support = map.report().min_support;
  m.max_cond = map.report().max_cond;
  for (Index v = 0; v < map.num_vertices(); ++v) {
    double sum = 0.0;
    Vec3 sx = Vec3::Zero();
    for (Index e = rs[v]; e < rs[v + 1]; ++e) {
      sum += map.values()[e];
      sx += map.values()[e] * X[map.columns()[e]];
    }
    m.unity = std::max(m.unity, std::abs(sum - 1.0));
    m.linear = std::max(m.linear, (sx - S[v]).norm() / delta);
  }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Vec3 t(5 * delta * u(rng), 5 * delta * u(rng), 5 * delta * u(rng));
  Mat3 A = Mat3::Identity();
  for (int a = 0; a < 9; ++a) A(a / 3, a % 3) += 0.2 * u(rng);
  field_error(map, X, A, t, delta, m.affine, m.f32, m.max_displacement);
  const Mat3 R90 = Eigen::AngleAxisd(std::numbers::pi / 2, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  field_error(map, X, R90, t, delta, m.rigid90, m.f32, m.max_displacement);
  field_error(map, X, random_rotation(rng), t, delta, m.rigid_rand, m.f32, m.max_displacement);
  m.max_displacement /= delta;
  m.f32_over_input_rounding =
      m.f32 / (static_cast<double>(std::numeric_limits<float>::epsilon()) * m.max_displacement);
  return m;
}

}  // namespace vascsim
