// The quadratic basis of the local fit (discretization.basis = quadratic, docs/model/05-local-fit.md
// section 5.1): the gradient it gives is exact for quadratic fields at every node (the linear basis's is not
// at a boundary node), and the energy built on it passes the checks the linear one passes (T3 rigid motions,
// T4 momentum, T5 forces = -grad U and Hessian products, T10 the stabiliser on the checkerboard), with the
// stabiliser now on the quadratic fit's residual (model/stabilizer_matrix).

#include <gtest/gtest.h>

#include <random>

#include "support/energy_checks.hpp"
#include "support/scene_errors.hpp"
#include "support/test_support.hpp"
#include "vascsim/model/discretization.hpp"
#include "vascsim/model/point_primitive_energy.hpp"
#include "vascsim/scene/scene.hpp"

#include <nlohmann/json.hpp>

namespace vascsim {
namespace {

using test::kDelta;

DiscretizationOptions quadratic() {
  DiscretizationOptions o;
  o.basis = GradientBasis::Quadratic;
  return o;
}

// u(X) = G X + 1/2 (X^T H_c X) e_c with random G and symmetric H_c, m.
struct QuadraticField {
  Mat3 G;
  Mat3 H[3];
  explicit QuadraticField(std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> uni(-1.0, 1.0);
    for (int k = 0; k < 9; ++k) G(k) = 0.1 * uni(rng);
    for (auto& h : H) {
      for (int k = 0; k < 9; ++k) h(k) = uni(rng) / (10.0 * kDelta);
      h = 0.5 * (h + h.transpose()).eval();
    }
  }
  Vec3 u(const Vec3& X) const {
    return G * X + 0.5 * Vec3(X.dot(H[0] * X), X.dot(H[1] * X), X.dot(H[2] * X));
  }
  Mat3 grad(const Vec3& X) const {
    Mat3 g = G;
    for (int c = 0; c < 3; ++c) g.row(c) += (H[c] * X).transpose();
    return g;
  }
};

// Exact to rounding at every node, boundary nodes included: the fit reproduces quadratic fields. The
// tolerance, 1e-9 of |grad u|, is the rounding of B_i^{-1} (its condition number is kept below 1e6 by the
// guard) on terms of size |u| / Delta. The linear basis misses by O(|H| Delta) at the boundary (measured 0.07
// relative), which shows the check can fail.
TEST(QuadraticBasis, QuadraticFieldsGiveTheExactGradientAtEveryNode) {
  const Material mat = test::tissue(1e5);
  const NodeCloud cloud = test::lattice(5, 0.2, 4);
  const Discretization quad(cloud, mat, quadratic());
  const Discretization lin(cloud, mat);
  const QuadraticField field(7);
  Vec3Array u(cloud.positions.size());
  for (std::size_t i = 0; i < u.size(); ++i) u[i] = field.u(cloud.positions[i]);
  double err_quad = 0.0, err_lin = 0.0, scale = 0.0;
  for (Index i = 0; i < quad.num_nodes(); ++i) {
    const Mat3 exact = field.grad(cloud.positions[static_cast<std::size_t>(i)]);
    scale = std::max(scale, exact.norm());
    err_quad = std::max(err_quad, (quad.displacement_gradient(i, u) - exact).norm());
    err_lin = std::max(err_lin, (lin.displacement_gradient(i, u) - exact).norm());
  }
  std::printf("[ quadratic ] max gradient error / max |grad u|: quadratic %.3g, linear %.3g\n",
              err_quad / scale, err_lin / scale);
  EXPECT_LT(err_quad, 1e-9 * scale);
  EXPECT_GT(err_lin, 1e-3 * scale);
}

// T3 and T4 for the quadratic basis with the stabiliser: a rigid motion gives no force (1e-10 E Delta^2, as
// RigidT3) and no energy beyond the rounding of the assembled stabiliser matrix: its null space holds the
// rigid motions only to the rounding of its entries, ~1e-16 of alpha mu Delta per entry on differences ~
// Delta, so 1e-14 alpha mu V (measured 1e-18 of it; the strain term alone is ~1e-33 J); and the forces of a
// large deformation sum to zero with zero torque (1e-12 relative, as MomentumT4: sum d_ik = 0 and rotation
// invariance hold for any fit without a constant term).
TEST(QuadraticBasis, RigidMotionIsFreeAndForcesConserveMomentum) {
  const Material mat = test::tissue(1e5);
  const Discretization disc(test::lattice(6, 0.2, 11), mat, quadratic());
  const PointPrimitiveEnergy energy(disc, {StrainMeasure::GreenHalf, 0.0, 0.5, {}, {}});
  const Mat3 R = Eigen::AngleAxisd(1.1, Vec3(0.3, -1.0, 0.4).normalized()).toRotationMatrix();
  Vec3Array x = disc.rest_positions();
  for (Vec3& p : x) p = R * p + Vec3(0.3, -0.2, 0.1) * kDelta;
  Vec3Array f;
  const double U = energy.forces(x, f);
  const double E = mat.youngs_modulus_pa;
  std::printf("[ quadratic ] rigid motion: energy %.3g J (alpha mu V = %.3g J), max force %.3g N\n", U,
              0.5 * mat.shear_modulus() * disc.total_volume(), test::max_norm(f));
  EXPECT_LT(std::abs(U), 1e-14 * 0.5 * mat.shear_modulus() * disc.total_volume());
  EXPECT_LT(test::max_norm(f), 1e-10 * E * kDelta * kDelta);

  x = test::large_deformation(disc.rest_positions(), 1);
  energy.forces(x, f);
  Vec3 sum = Vec3::Zero(), torque = Vec3::Zero();
  for (std::size_t i = 0; i < x.size(); ++i) {
    sum += f[i];
    torque += x[i].cross(f[i]);
  }
  EXPECT_LE(sum.norm(), 1e-12 * test::max_norm(f));
  EXPECT_LE(torque.norm(), 1e-12 * test::max_norm(f) * test::max_norm(x));
}

// T5: forces are minus the energy's gradient (central differences, 1e-6 as ForceEnergyT5), for the strain
// energy with the stabiliser and for the stabiliser matrix alone (its force is the difference of alpha 0.5
// and 0); and the Hessian product is the derivative of the forces (1e-6, as
// HessianProductMatchesForceDifferences).
TEST(QuadraticBasis, ForcesAndHessianAreTheEnergysDerivatives) {
  const Material mat = test::tissue(1e5);
  const Discretization disc(test::lattice(6, 0.2, 11), mat, quadratic());
  test::expect_stabiliser_derivatives<PointPrimitiveEnergy>(
      disc, EnergyOptions{StrainMeasure::GreenHalf, 0.0, 0.5, {}, {}});
}

// T10: the stabiliser on the quadratic fit's residual vanishes on quadratic fields (bending is not penalised:
// rounding of the assembled matrix only, 1e-14 alpha mu V as above; a stabiliser on the affine fit's residual
// gives 2e-3 of alpha mu V here) and penalises the checkerboard mode (above a tenth of
// its natural scale alpha mu (a / Delta)^2 V, as T10).
TEST(QuadraticBasis, StabiliserIgnoresQuadraticFieldsAndPenalisesTheCheckerboard) {
  const Material mat = test::tissue(1e5);
  const Discretization disc(test::lattice(6, 0.0, 1), mat, quadratic());
  const double alpha = 0.1;
  const PointPrimitiveEnergy energy(disc, {StrainMeasure::GreenHalf, 0.0, alpha, {}, {}});
  const QuadraticField field(3);
  Vec3Array x = disc.rest_positions();
  for (Vec3& p : x) p += field.u(p);
  const double U_quadratic = energy.energy(x).stabilizer;
  std::printf("[ quadratic ] stabiliser energy of a quadratic field: %.3g of alpha mu V\n",
              U_quadratic / (alpha * mat.shear_modulus() * disc.total_volume()));
  EXPECT_LE(std::abs(U_quadratic), 1e-14 * alpha * mat.shear_modulus() * disc.total_volume());

  const double a = 0.01 * kDelta;
  x = disc.rest_positions();
  for (Vec3& p : x) {
    const int parity = static_cast<int>(std::lround(p.x() / kDelta + p.y() / kDelta + p.z() / kDelta)) % 2;
    p.z() += parity ? a : -a;
  }
  const double scale = alpha * mat.shear_modulus() * (a / kDelta) * (a / kDelta) * disc.total_volume();
  EXPECT_GT(energy.energy(x).stabilizer, 0.1 * scale);
}

// A model whose constraints assume the linear fit (xpbd's stabiliser pairs hold F_i fixed) refuses the
// quadratic basis at the scene key, naming the models that take it.
TEST(QuadraticBasis, ModelsThatAssumeTheLinearFitRefuseItAtTheKey) {
  nlohmann::json doc = nlohmann::json::parse(R"({
    "name": "q", "model": "xpbd",
    "geometry": { "type": "box", "min_m": [0, 0, 0], "max_m": [0.004, 0.004, 0.004], "node_spacing_m": 0.001 },
    "material": { "youngs_modulus_pa": 1e5, "poisson_ratio": 0.45, "density_kg_m3": 1060 },
    "discretization": { "basis": "quadratic" },
    "regions": [ { "name": "base", "select": { "type": "box", "max_m": [1, 1, 0] }, "bc": { "type": "fixed" } } ]
  })");
  const std::string m = test::scene_error(doc, "q.json");
  EXPECT_NE(m.find("discretization.basis"), std::string::npos) << m;
  EXPECT_NE(m.find("quasi_static"), std::string::npos) << m;
  doc["model"] = "quasi_static";
  EXPECT_NO_THROW(parse_scene(doc, "q.json"));
}

}  // namespace
}  // namespace vascsim
