#pragma once
// Checks shared by the energy tests: the large deformation of the T4/T5 checks, and forces against central
// differences of the energy (docs/validation.md T5, docs/validation.md).

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

#include <gtest/gtest.h>

#include "vascsim/core/types.hpp"
#include "vascsim/model/discretization.hpp"
#include "vascsim/model/energy_hessian.hpp"
#include "vascsim/model/material.hpp"

#include "support/test_support.hpp"

namespace vascsim::test {

// docs/validation.md T4/T5 deformation: x = R (I + 0.1 rand) X plus 0.05 Delta noise (rand, noise uniform in
// [-1, 1]).
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

// The patch test's measure: the largest error over the nodes of the fitted gradient of the affine field u = A
// X.
inline double max_affine_gradient_error(const Discretization& d, const Mat3& A) {
  Vec3Array u(d.rest_positions().size());
  for (std::size_t i = 0; i < u.size(); ++i) u[i] = A * d.rest_positions()[i];
  double err = 0.0;
  for (Index i = 0; i < d.num_nodes(); ++i) err = std::max(err, (d.displacement_gradient(i, u) - A).norm());
  return err;
}

inline double max_norm(const Vec3Array& a) {
  double m = 0.0;
  for (const Vec3& v : a) m = std::max(m, v.norm());
  return m;
}

// T3 and T4 for an energy whose fit reproduces affine fields: a rigid motion (a rotation and a shift) stores
// no energy (1e-14 of mu V / 2: rounding) and moves no node (1e-10 E Delta^2, Delta the lattice's largest
// spacing: a node's force is a stress times its own area, of order its spacing squared), and at a large
// deformation the forces sum to zero and have no torque (1e-12 relative: rounding of sums of a few hundred
// terms). The bounds' reasons are QuadraticBasis.RigidMotionIsFreeAndForcesConserveMomentum's.
template <class Energy>
void expect_rigid_motion_free_and_momentum(const Energy& energy, const Material& mat,
                                           double spacing = kDelta) {
  const auto& disc = energy.discretization();
  const Mat3 R = Eigen::AngleAxisd(1.1, Vec3(0.3, -1.0, 0.4).normalized()).toRotationMatrix();
  Vec3Array x = disc.rest_positions();
  for (Vec3& p : x) p = R * p + Vec3(0.3, -0.2, 0.1) * kDelta;
  Vec3Array f;
  const double U = energy.forces(x, f);
  EXPECT_LT(std::abs(U), 1e-14 * 0.5 * mat.shear_modulus() * disc.total_volume());
  EXPECT_LT(max_norm(f), 1e-10 * mat.youngs_modulus_pa * spacing * spacing);

  x = large_deformation(disc.rest_positions(), 1);
  energy.forces(x, f);
  Vec3 sum = Vec3::Zero(), torque = Vec3::Zero();
  for (std::size_t i = 0; i < x.size(); ++i) {
    sum += f[i];
    torque += x[i].cross(f[i]);
  }
  EXPECT_LE(sum.norm(), 1e-12 * max_norm(f));
  EXPECT_LE(torque.norm(), 1e-12 * max_norm(f) * max_norm(x));
}

// max over 30 random DOFs of |f + dU/dx| / max|f|, with dU/dx by central differences of step 1e-7 Delta.
inline double fd_force_error(const std::function<double(const Vec3Array&)>& U, const Vec3Array& f,
                             Vec3Array x) {
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

// max_i |H v + (f(x + eps v) - f(x - eps v)) / (2 eps)| / max_i |H v| for a random v of size Delta (seed):
// the Hessian product against a central difference of the forces (T5). `hessian_product(x, v, Hv)` and
// `forces(x, f)` are the energy's. Truncation ~eps^2, rounding ~1e-15 / eps: about 1e-9 relative at eps =
// 1e-6.
template <class Energy>
double fd_hessian_error(const Energy& energy, const Vec3Array& x, std::uint64_t seed, double eps = 1e-6) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  Vec3Array v(x.size());
  for (Vec3& p : v) p = kDelta * Vec3(uni(rng), uni(rng), uni(rng));
  Vec3Array Hv, fp, fm, xp(x), xm(x);
  energy.hessian_product(x, v, Hv);
  for (std::size_t i = 0; i < x.size(); ++i) {
    xp[i] += eps * v[i];
    xm[i] -= eps * v[i];
  }
  energy.forces(xp, fp);
  energy.forces(xm, fm);
  double err = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i)
    err = std::max(err, (Hv[i] + (fp[i] - fm[i]) / (2 * eps)).norm());
  return err / max_norm(Hv);
}

// T5 for an energy with a stabiliser: on a jittered lattice at the large deformation, the forces of `with`
// (the energy's options, a stabiliser among them) against central differences of its energy, the stabiliser's
// forces alone (`with`'s minus those of the same discretisation without a stabiliser) against the derivative
// of its stabiliser energy, and its Hessian product against differences of its forces, each to 1e-6 relative
// (the differences' own error at eps = 1e-6); the stabiliser's force must not be zero, or the check is
// vacuous.
template <class Energy, class Discretization, class Options>
void expect_stabiliser_derivatives(const Discretization& disc, const Options& with_options) {
  const Vec3Array x = large_deformation(disc.rest_positions(), 2);
  const Energy with(disc, with_options);
  Options no_stabiliser = with_options;
  no_stabiliser.stabilizer_alpha = 0.0;
  const Energy without(disc, no_stabiliser);
  Vec3Array f, f0;
  with.forces(x, f);
  without.forces(x, f0);
  EXPECT_LE(fd_force_error([&](const Vec3Array& y) { return with.energy(y).total(); }, f, x), 1e-6);
  for (std::size_t i = 0; i < f.size(); ++i) f0[i] = f[i] - f0[i];
  EXPECT_LE(fd_force_error([&](const Vec3Array& y) { return with.energy(y).stabilizer; }, f0, x), 1e-6);
  EXPECT_GT(max_norm(f0), 0.0);
  EXPECT_LE(fd_hessian_error(with, x, 6), 1e-6);
}

// The assembled Hessian (EnergyHessian, full stencil) against the Hessian product at x, on a fixed smooth
// vector: the largest difference over the largest product, for a bound of 1e-10 (two summation orders of the
// same terms).
template <class Energy>
double assembled_hessian_error(const Energy& energy, const Vec3Array& x) {
  EnergyHessian H(energy);
  H.assemble(x);
  Vec3Array v(x.size()), Hv;
  for (std::size_t i = 0; i < v.size(); ++i)
    v[i] = kDelta * Vec3(std::sin(1.0 + static_cast<double>(i)), std::cos(2.0 * static_cast<double>(i)),
                         std::sin(0.3 * static_cast<double>(i)));
  energy.hessian_product(x, v, Hv);
  const Eigen::Map<const Eigen::VectorXd> vv(v[0].data(), 3 * static_cast<Eigen::Index>(v.size()));
  const Eigen::VectorXd assembled = H.matrix() * vv;
  double err = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    err = std::max(err, (assembled.segment<3>(3 * static_cast<Eigen::Index>(i)) - Hv[i]).norm());
    scale = std::max(scale, Hv[i].norm());
  }
  return err / scale;
}

}  // namespace vascsim::test
