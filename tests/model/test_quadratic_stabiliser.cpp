// The stabiliser on a quadratic fit's residuals with the linear basis (energy.stabilizer_fit = quadratic,
// docs/model/09-volume-term-and-stabiliser.md section 9.3): the energy built with it passes T3 (rigid motions
// cost nothing), T5 (forces = -grad U, Hessian products = the forces' derivative), and the scene gives it to
// the equilibrium models on walls only, refusing it where the constraints assume the linear fit. T10 (the
// checkerboard, bending left alone) is in test_stiffness_modes.cpp.

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <random>

#include "support/energy_checks.hpp"
#include "support/scene_errors.hpp"
#include "support/test_support.hpp"
#include "vascsim/model/discretization.hpp"
#include "vascsim/model/point_primitive_energy.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim {
namespace {

using test::kDelta;

EnergyOptions quadratic_fit(double alpha) {
  EnergyOptions o{StrainMeasure::GreenHalf, 0.0, alpha, {}, {}};
  o.stabilizer_fit = StabilizerFit::Quadratic;
  return o;
}

// T5 on a jittered lattice at a large deformation, as for the other terms: the stabiliser's forces against a
// central difference of its energy (1e-6 relative, the finite difference's own error at this step), the total
// likewise, and the Hessian product against a central difference of the forces (1e-6 of |H v|).
TEST(QuadraticFitStabiliser, ForcesAndHessianAreTheEnergysDerivatives) {
  const Material mat = test::tissue(1e5);
  const Discretization disc(test::lattice(6, 0.2, 11), mat);
  test::expect_stabiliser_derivatives<PointPrimitiveEnergy>(disc, quadratic_fit(0.5));
}

// Residuals ask for the forces without the energy (the stabiliser's matrix then skips its energy sum): the
// forces are the same to the bit (the sum never enters them), the energy is NaN rather than a partial sum,
// and with the energy it is energy(x)'s total (to 1e-12 relative: the same terms summed in another order).
TEST(QuadraticFitStabiliser, ForcesWithoutTheEnergyAreTheSameForces) {
  const Material mat = test::tissue(1e5);
  const Discretization disc(test::lattice(6, 0.2, 11), mat);
  const PointPrimitiveEnergy energy(disc, quadratic_fit(0.5));
  Vec3Array x = disc.rest_positions();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.2 * kDelta, 0.2 * kDelta);
  for (Vec3& p : x) p += Vec3(0.1 * p.x() + u(rng), u(rng), -0.05 * p.z() + u(rng));
  Vec3Array with, without;
  const double U = energy.forces(x, with);
  EXPECT_TRUE(std::isnan(energy.forces(x, without, false)));
  ASSERT_EQ(with.size(), without.size());
  for (std::size_t i = 0; i < with.size(); ++i) EXPECT_EQ(with[i], without[i]) << "node " << i;
  EXPECT_NEAR(U, energy.energy(x).total(), 1e-12 * std::abs(U));
  EXPECT_GT(std::abs(energy.energy(x).stabilizer), 0.0);
}

// T3: a rigid motion (rotation by 0.7 rad and a translation of 3 spacings) costs no stabiliser energy and no
// force: rounding only, 1e-12 of the energy the same stabiliser gives a 1 % checkerboard (which is O(1e-4 mu
// V)).
TEST(QuadraticFitStabiliser, RigidMotionIsFree) {
  const Material mat = test::tissue(1e5);
  const Discretization disc(test::lattice(5, 0.2, 3), mat);
  const PointPrimitiveEnergy energy(disc, quadratic_fit(0.1));
  const Mat3 R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  Vec3Array x = disc.rest_positions();
  for (Vec3& p : x) p = R * p + Vec3(3 * kDelta, -kDelta, 2 * kDelta);
  Vec3Array f;
  energy.forces(x, f);
  const double scale = 0.1 * mat.shear_modulus() * 1e-4 * disc.total_volume();
  EXPECT_LE(std::abs(energy.energy(x).stabilizer), 1e-12 * scale);
  EXPECT_LE(test::max_norm(f), 1e-9 * mat.youngs_modulus_pa * kDelta * kDelta);
}

nlohmann::json tube_scene(const std::string& model, const std::string& geometry) {
  nlohmann::json doc = nlohmann::json::parse(R"({
    "name": "fit", "model": "quasi_static",
    "material": { "youngs_modulus_pa": 1e5, "poisson_ratio": 0.45, "density_kg_m3": 1060 },
    "regions": [ { "name": "base", "select": { "type": "box", "max_m": [1, 1, 0] }, "bc": { "type": "fixed" } } ]
  })");
  doc["model"] = model;
  if (geometry == "tube")
    doc["geometry"] = {{"type", "tube"},
                       {"outer_radius_m", 1.5e-3},
                       {"wall_thickness_m", 0.3e-3},
                       {"length_m", 3e-3},
                       {"node_spacing_m", 0.3e-3}};
  else
    doc["geometry"] = {
        {"type", "box"}, {"min_m", {0, 0, 0}}, {"max_m", {0.004, 0.004, 0.004}}, {"node_spacing_m", 0.001}};
  return doc;
}

// The default: quadratic for quasi_static and implicit on a wall, the linear fit's elsewhere (a box; the
// models tuned with it; formulation paper_literal has no stabiliser). Asked of xpbd, the key is an input
// error naming the models that take it.
TEST(QuadraticFitStabiliser, IsTheEquilibriumModelsDefaultOnAWallAndRefusedByXpbd) {
  EXPECT_EQ(parse_scene(tube_scene("quasi_static", "tube"), "t.json").energy.stabilizer_fit,
            StabilizerFit::Quadratic);
  EXPECT_EQ(parse_scene(tube_scene("implicit", "tube"), "t.json").energy.stabilizer_fit,
            StabilizerFit::Quadratic);
  EXPECT_EQ(parse_scene(tube_scene("quasi_static", "box"), "t.json").energy.stabilizer_fit,
            StabilizerFit::Basis);
  EXPECT_EQ(parse_scene(tube_scene("xpbd", "tube"), "t.json").energy.stabilizer_fit, StabilizerFit::Basis);
  EXPECT_EQ(parse_scene(tube_scene("explicit", "tube"), "t.json").energy.stabilizer_fit,
            StabilizerFit::Basis);
  nlohmann::json asked = tube_scene("xpbd", "tube");
  asked["energy"] = {{"stabilizer_fit", "quadratic"}};
  const std::string m = test::scene_error(asked, "t.json");
  EXPECT_NE(m.find("energy.stabilizer_fit"), std::string::npos) << m;
  EXPECT_NE(m.find("quasi_static"), std::string::npos) << m;
  nlohmann::json box = tube_scene("quasi_static", "box");
  box["energy"] = {{"stabilizer_fit", "quadratic"}};
  EXPECT_EQ(parse_scene(box, "t.json").energy.stabilizer_fit, StabilizerFit::Quadratic);
}

}  // namespace
}  // namespace vascsim
