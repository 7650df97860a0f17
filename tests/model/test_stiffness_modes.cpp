// docs/validation.md (tests T1-T15), T6 (stiffness scaling: SVK matches linear elasticity, the literal strain
// is 4x stiffer) and T10 (nodal-integration zero-energy modes and the stabiliser that removes them).

#include <gtest/gtest.h>

#include "support/test_support.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <random>
#include <sstream>
#include <string>

#include "vascsim/geometry/generators.hpp"
#include "vascsim/model/discretization.hpp"
#include "vascsim/model/point_primitive_energy.hpp"

namespace {

using namespace vascsim;
using test::kDelta;
using test::record;

NodeCloud regular_lattice(int cells) {
  return test::lattice(cells);
}

Material tissue(double nu) {
  return test::tissue(5e5, nu);
}

TEST(StiffnessT6, UniaxialStrainEnergyMatchesLinearElasticity) {
  const double e = 1e-4;
  for (double nu : {0.3, 0.45}) {
    const Material mat = tissue(nu);
    const Discretization disc(regular_lattice(4), mat);  // 5^3 lattice, tet-partition volumes
    const double V = std::pow(4 * kDelta, 3);
    // Tet-partition volumes sum to the box volume exactly (so U_lin below uses the true volume).
    ASSERT_NEAR(disc.total_volume(), V, 1e-12 * V);
    const PointPrimitiveEnergy svk(disc, {StrainMeasure::GreenHalf, 0.0, 0.1, {}, {}});
    const PointPrimitiveEnergy literal(disc, {StrainMeasure::MuellerNoHalf, 0.0, 0.0, {}, {}});
    const double U_lin = 0.5 * mat.p_wave_modulus() * e * e * V;
    for (int axis = 0; axis < 3; ++axis) {
      Vec3Array x = disc.rest_positions();
      for (Vec3& p : x) p[axis] *= 1.0 + e;
      const double r_svk = svk.energy(x).total() / U_lin, r_lit = literal.energy(x).total() / U_lin;
      // docs/validation.md T6: [0.999, 1.001] and [3.996, 4.004]. The exact ratios are (1 + e/2)^2 = 1.0001
      // and 4.0004 (Green strain e + e^2/2), since the patch test makes F exact at every node.
      // Measured 1.0001 and 4.0004 for nu = 0.3 and 0.45.
      EXPECT_GE(r_svk, 0.999) << "nu " << nu << " axis " << axis;
      EXPECT_LE(r_svk, 1.001) << "nu " << nu << " axis " << axis;
      EXPECT_GE(r_lit, 3.996) << "nu " << nu << " axis " << axis;
      EXPECT_LE(r_lit, 4.004) << "nu " << nu << " axis " << axis;
      if (axis == 0) {
        record(nu < 0.4 ? "U_svk_over_U_lin_nu03" : "U_svk_over_U_lin_nu045", r_svk);
        record(nu < 0.4 ? "U_lit_over_U_lin_nu03" : "U_lit_over_U_lin_nu045", r_lit);
      }
    }
  }
}

// Regular 9^3 lattice with the checkerboard displacement u_i = a e (-1)^(i+j+k).
struct Checkerboard {
  static constexpr int kCells = 8;
  Material mat = tissue(0.45);
  Discretization disc{regular_lattice(kCells), mat};
  double a = 0.05 * kDelta;
  Vec3 dir = Vec3(1.0, 2.0, 3.0).normalized();

  Index id(int i, int j, int k) const { return i + (kCells + 1) * (j + (kCells + 1) * k); }
  Vec3Array positions() const {
    Vec3Array x = disc.rest_positions();
    for (int k = 0; k <= kCells; ++k)
      for (int j = 0; j <= kCells; ++j)
        for (int i = 0; i <= kCells; ++i) x[id(i, j, k)] += ((i + j + k) % 2 ? -a : a) * dir;
    return x;
  }
  // Interior: every neighbour offset (|offset_c| <= 1 for h = 2 Delta) stays inside the lattice.
  bool interior(int i, int j, int k) const {
    return std::min({i, j, k}) >= 1 && std::max({i, j, k}) <= kCells - 1;
  }
};

TEST(ZeroModesT10, CheckerboardHasNoStrainAtInteriorNodes) {
  const Checkerboard cb;
  const Vec3Array x = cb.positions();
  double interior_max = 0.0, boundary_max = 0.0;
  for (int k = 0; k <= Checkerboard::kCells; ++k)
    for (int j = 0; j <= Checkerboard::kCells; ++j)
      for (int i = 0; i <= Checkerboard::kCells; ++i) {
        const double g = (cb.disc.deformation_gradient(cb.id(i, j, k), x) - Mat3::Identity()).norm();
        double& worst = cb.interior(i, j, k) ? interior_max : boundary_max;
        worst = std::max(worst, g);
      }
  // docs/validation.md T10: interior |F_i - I| <= 1e-12, documenting the defect (symmetric neighbourhoods
  // cancel the mode exactly; prototype 3e-16). Measured 7.7e-16.
  EXPECT_LE(interior_max, 1e-12);
  // The same measure is O(a / Delta) at boundary nodes, so it is not vacuous there (prototype 1.8e-3
  // for a smaller a). Measured 0.065.
  EXPECT_GT(boundary_max, 1e-3);
  record("interior_max_F_minus_I", interior_max);
  record("boundary_max_F_minus_I", boundary_max);
}

TEST(ZeroModesT10, StabiliserPenalisesCheckerboardButNotAffineFields) {
  const Checkerboard cb;
  const double mu = cb.mat.shear_modulus(), E = cb.mat.youngs_modulus_pa, alpha = 0.1;
  const PointPrimitiveEnergy energy(cb.disc, {StrainMeasure::GreenHalf, 0.0, alpha, {}, {}});
  const double U_hg = energy.energy(cb.positions()).stabilizer;
  // Scale of the stabiliser energy: alpha mu (a / Delta)^2 per unit volume (r_ij ~ 2a, |X_ij| ~ Delta).
  const double scale = alpha * mu * (cb.a / kDelta) * (cb.a / kDelta) * cb.disc.total_volume();
  // docs/validation.md T10: "> 0"; asserted as > 0.1 of its natural scale so rounding noise cannot pass.
  // Measured 0.90x the scale.
  EXPECT_GT(U_hg, 0.1 * scale);
  record("stabiliser_energy_over_scale", U_hg / scale);

  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  double U_affine = 0.0;
  for (int trial = 0; trial < 3; ++trial) {
    Mat3 B;
    for (int c = 0; c < 9; ++c) B(c) = uni(rng);
    const Mat3 A = Mat3::Identity() + 0.2 * B / B.norm();
    const Vec3 t = kDelta * Vec3(uni(rng), uni(rng), uni(rng));
    Vec3Array x = cb.disc.rest_positions();
    for (Vec3& p : x) p = A * p + t;
    U_affine = std::max(U_affine, std::abs(energy.energy(x).stabilizer));
  }
  // docs/validation.md T10: <= 1e-20 E Delta^3 for any affine field (the local fit is exact, so only rounding
  // of r_ij ~ 1e-16 Delta remains). Measured 1.7e-33 J vs 5e-25 J.
  EXPECT_LE(U_affine, 1e-20 * E * kDelta * kDelta * kDelta);
  record("stabiliser_energy_affine_J", U_affine);
}

// Bending about y: u_x = -kappa x z, u_z = kappa x^2 / 2 (a quadratic field), curvature kappa (1/m).
Vec3Array bent(const Discretization& disc, double kappa) {
  Vec3Array x = disc.rest_positions();
  for (Vec3& p : x) {
    const Vec3 X = p;
    p.x() += -kappa * X.x() * X.z();
    p.z() += 0.5 * kappa * X.x() * X.x();
  }
  return x;
}

// energy.stabilizer_fit = quadratic (docs/model/09-volume-term-and-stabiliser.md section 9.3): the stabiliser
// on the residuals of a quadratic fit over the same neighbourhood. It must still penalise the checkerboard
// (which no quadratic reproduces), and it must leave a quadratic field, such as bending, to the strain
// energy, where the linear fit's residuals penalise it.
TEST(ZeroModesT10, QuadraticResidualStabiliserLeavesBendingToTheStrain) {
  const Checkerboard cb;
  const double mu = cb.mat.shear_modulus(), E = cb.mat.youngs_modulus_pa, alpha = 0.1;
  EnergyOptions options{StrainMeasure::GreenHalf, 0.0, alpha, {}, {}};
  options.stabilizer_fit = StabilizerFit::Quadratic;
  const PointPrimitiveEnergy quadratic_fit(cb.disc, options);
  const double scale = alpha * mu * (cb.a / kDelta) * (cb.a / kDelta) * cb.disc.total_volume();
  const double U_checker = quadratic_fit.energy(cb.positions()).stabilizer;
  // The same bound as the linear fit's (0.1 of the natural scale): the mode stays penalised. Measured 0.61x
  // (the linear fit: 0.90x).
  EXPECT_GT(U_checker, 0.1 * scale);
  record("quadratic_stabiliser_checkerboard_over_scale", U_checker / scale);

  EXPECT_LE(std::abs(quadratic_fit.energy(bent(cb.disc, 1e-3 / kDelta)).stabilizer),
            1e-12 * E * std::pow(kDelta, 3));

  // A plate of three node layers (0.3 mm thick) whose nodes are twice as far apart along it (8 x 8 x 2 cells
  // of 0.3 x 0.3 x 0.15 mm), with supports that follow the wall (stretch 2), bent about y: the vein's wall at
  // 0.3 mm.
  BoxSpec plate;
  plate.max_m = Vec3(2.4e-3, 2.4e-3, 0.3e-3);
  plate.cells = Eigen::Vector3i(8, 8, 2);
  const NodeCloud cloud = make_box(plate);
  DiscretizationOptions wall_support;
  wall_support.wall_normals.assign(cloud.positions.size(), Vec3::UnitZ());
  for (const Vec3& p : cloud.positions) wall_support.wall_depths.push_back(p.z());
  wall_support.wall_stretch = 2.0;
  wall_support.max_growths = 10;  // the corner nodes, as in a scene (discretization.max_growths)
  const Discretization wall(cloud, cb.mat, wall_support);
  EnergyOptions wall_options{StrainMeasure::GreenHalf, 0.0, alpha, {}, {}};
  const PointPrimitiveEnergy wall_linear(wall, wall_options);
  wall_options.stabilizer_fit = StabilizerFit::Quadratic;
  const PointPrimitiveEnergy wall_quadratic(wall, wall_options);
  const Vec3Array x = bent(wall, 1.0);  // 1/m: 1e-4 strain at the surfaces
  const double U_linear = wall_linear.energy(x).stabilizer, U_quadratic = wall_quadratic.energy(x).stabilizer;
  const double U_strain = wall_quadratic.energy(x).strain;
  // The linear fit's residuals of a bending field are the quadratic part of kappa X X / 2 that no affine map
  // absorbs, so its stabiliser takes a share of the bending energy (bound 1e-4, so that it cannot be
  // rounding; measured 2.1e-3 on this plate, more where the field varies faster than a support, as under a
  // tool). The quadratic fit reproduces the field, so only rounding remains (bound 1e-12 of the strain
  // energy: r_ij is rounding, ~1e-16 |X_ij|; measured 8e-18).
  EXPECT_GT(U_linear, 1e-4 * U_strain);
  EXPECT_LE(std::abs(U_quadratic), 1e-12 * U_strain);
  record("bent_wall_stabiliser_over_strain_linear_fit", U_linear / U_strain);
  record("bent_wall_stabiliser_over_strain_quadratic_fit", U_quadratic / U_strain);
  std::printf(
      "[ stabiliser ] bent 3-layer wall: stabiliser / strain energy %.3g (linear fit), %.3g (quadratic "
      "fit)\n",
      U_linear / U_strain, U_quadratic / U_strain);
}

}  // namespace
