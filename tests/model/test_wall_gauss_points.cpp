// Through-wall Gauss points (discretization.wall_quadrature = gauss, docs/model.md section 4.4): each node's strain
// energy is evaluated at two Gauss points across its slab of the wall, with the gradient its fit gives there. A
// bending field's energy is then exact over the tet partition's volumes (the nodal sum overestimates it by half on a
// three-layer wall), and the energy passes the checks every basis passes: T3 rigid motions, T4 momentum, T5 forces =
// -grad U and Hessian products, and the assembled Hessian equals the Hessian product.

#include <gtest/gtest.h>

#include <cmath>

#include "support/energy_checks.hpp"
#include "support/scene_errors.hpp"
#include "support/test_support.hpp"
#include "vascsim/geometry/generators.hpp"
#include "vascsim/model/discretization.hpp"
#include "vascsim/model/energy_hessian.hpp"
#include "vascsim/model/point_primitive_energy.hpp"
#include "vascsim/scene/scene.hpp"

#include <nlohmann/json.hpp>

namespace vascsim {
namespace {

using test::kDelta;

constexpr int kLayers = 3;  // nodes through the wall
constexpr double kThickness = (kLayers - 1) * kDelta;

// A flat wall: a box lattice of `cells` x `cells` cells along it and kLayers node layers through it (normal z).
NodeCloud wall_lattice(int cells, double jitter = 0.0) {
  BoxSpec spec;
  spec.max_m = Vec3(cells * kDelta, cells * kDelta, kThickness);
  spec.cells = Eigen::Vector3i(cells, cells, kLayers - 1);
  spec.jitter = jitter;
  spec.seed = 5;
  return make_box(spec);
}

// The wall support, basis and depths the simulation fills for a vessel, here for the flat wall.
DiscretizationOptions wall_options(const NodeCloud& cloud, GradientBasis basis,
                                   DiscretizationOptions::WallQuadrature quadrature) {
  DiscretizationOptions o;
  o.basis = basis;
  o.support = DiscretizationOptions::Support::Wall;
  o.wall_normals.assign(cloud.positions.size(), Vec3::UnitZ());
  for (const Vec3& p : cloud.positions) o.wall_depths.push_back(p.z());
  o.wall_thickness_m = kThickness;
  o.wall_layer_spacing_m = kDelta;
  o.wall_quadrature = quadrature;
  return o;
}

// The small-strain energy 1/2 u^T H(X) u of u (the Hessian product at rest), J.
double small_strain_energy(const PointPrimitiveEnergy& energy, const Vec3Array& u) {
  Vec3Array Hu;
  energy.hessian_product(energy.discretization().rest_positions(), u, Hu);
  double U = 0.0;
  for (std::size_t i = 0; i < u.size(); ++i) U += 0.5 * u[i].dot(Hu[i]);
  return U;
}

// Pure bending about the mid-surface: u = (-k x (z - t/2), 0, k x^2 / 2) has the strain eps_xx = -k (z - t/2) and no
// other, so its small-strain energy is (mu + lambda / 2) k^2 A t^3 / 12 exactly. The wall-quadratic fit reproduces
// the field at every node; with Gauss points the energy must match to rounding (1e-9: the fits' B_i^{-1} with
// condition below 1e6, as in the basis's own gradient test). At the nodes alone the tet partition's weights are the
// trapezoid's across the layers: 1.5 times the exact energy with three layers (asserted above 1.4, which shows the
// check can fail).
TEST(WallGaussPoints, IntegrateABendingFieldsEnergyExactlyOverTheTetPartition) {
  const Material mat = test::tissue(1e5);
  const int cells = 6;
  const NodeCloud cloud = wall_lattice(cells);
  const double k = 0.01 / kDelta;
  Vec3Array u;
  for (const Vec3& p : cloud.positions) u.push_back(Vec3(-k * p.x() * (p.z() - 0.5 * kThickness), 0.0, 0.5 * k * p.x() * p.x()));
  const double area = cells * kDelta * cells * kDelta;
  const double exact =
      (mat.shear_modulus() + 0.5 * mat.lame_lambda()) * k * k * area * kThickness * kThickness * kThickness / 12.0;
  const EnergyOptions eo{StrainMeasure::GreenHalf, 0.0, 0.0, {}, {}};
  using Q = DiscretizationOptions::WallQuadrature;
  const Discretization gauss(cloud, mat, wall_options(cloud, GradientBasis::WallQuadratic, Q::Gauss));
  const Discretization nodes(cloud, mat, wall_options(cloud, GradientBasis::WallQuadratic, Q::Nodes));
  ASSERT_EQ(gauss.energy_points(), 2);
  const double at_points = small_strain_energy(PointPrimitiveEnergy(gauss, eo), u) / exact;
  const double at_nodes = small_strain_energy(PointPrimitiveEnergy(nodes, eo), u) / exact;
  std::printf("[ wall Gauss points ] bending energy / exact: %.12f with Gauss points, %.4f at the nodes\n", at_points,
              at_nodes);
  EXPECT_NEAR(at_points, 1.0, 1e-9);
  EXPECT_GT(at_nodes, 1.4);
}

// The points sit inside the node's slab of the wall: a surface node's both on the wall's side of it, the middle
// layer's symmetric about it, every one within half a layer step (exact placements, to rounding).
TEST(WallGaussPoints, LieInsideEachNodesSlabOfTheWall) {
  const Material mat = test::tissue(1e5);
  const NodeCloud cloud = wall_lattice(4);
  const Discretization disc(cloud, mat,
                            wall_options(cloud, GradientBasis::WallQuadratic, DiscretizationOptions::WallQuadrature::Gauss));
  const double spread = 0.25 * kDelta / std::sqrt(3.0);
  for (Index i = 0; i < disc.num_nodes(); ++i) {
    const double z = disc.rest_positions()[static_cast<std::size_t>(i)].z();
    const double centre = z < 0.5 * kDelta ? 0.25 * kDelta : z > 1.5 * kDelta ? -0.25 * kDelta : 0.0;
    const double half = z < 0.5 * kDelta || z > 1.5 * kDelta ? spread : 2.0 * spread;
    EXPECT_NEAR(disc.point_offset(i, 0), centre - half, 1e-12 * kDelta) << "node " << i;
    EXPECT_NEAR(disc.point_offset(i, 1), centre + half, 1e-12 * kDelta) << "node " << i;
  }
}

// T3 and T4 (the bounds and their reasons of WallQuadraticBasis.RigidMotionIsFreeAndForcesConserveMomentum): the
// gradient's derivative across the wall is zero on every affine field, so a rigid motion moves no point.
TEST(WallGaussPoints, RigidMotionIsFreeAndForcesConserveMomentum) {
  const Material mat = test::tissue(1e5);
  const NodeCloud cloud = wall_lattice(5, 0.2);
  const Discretization disc(cloud, mat,
                            wall_options(cloud, GradientBasis::WallQuadratic, DiscretizationOptions::WallQuadrature::Gauss));
  EnergyOptions eo{StrainMeasure::GreenHalf, 0.0, 0.5, {}, {}};
  eo.stabilizer_fit = StabilizerFit::Quadratic;
  const PointPrimitiveEnergy energy(disc, eo);
  const Mat3 R = Eigen::AngleAxisd(1.1, Vec3(0.3, -1.0, 0.4).normalized()).toRotationMatrix();
  Vec3Array x = disc.rest_positions();
  for (Vec3& p : x) p = R * p + Vec3(0.3, -0.2, 0.1) * kDelta;
  Vec3Array f;
  const double U = energy.forces(x, f);
  EXPECT_LT(std::abs(U), 1e-14 * 0.5 * mat.shear_modulus() * disc.total_volume());
  EXPECT_LT(test::max_norm(f), 1e-10 * mat.youngs_modulus_pa * kDelta * kDelta);

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

// T5 with both curvature bases (tolerances of QuadraticBasis.ForcesAndHessianAreTheEnergysDerivatives), and the
// assembled Hessian against the Hessian product at the same large deformation (1e-10 relative: two summation orders
// of the same terms).
TEST(WallGaussPoints, ForcesAndHessianAreTheEnergysDerivatives) {
  const Material mat = test::tissue(1e5);
  const NodeCloud cloud = wall_lattice(5, 0.2);
  for (GradientBasis basis : {GradientBasis::WallQuadratic, GradientBasis::Quadratic}) {
    DiscretizationOptions o = wall_options(cloud, basis, DiscretizationOptions::WallQuadrature::Gauss);
    o.max_growths = 6;  // the quadratic basis's surface supports must reach the far layer
    const Discretization disc(cloud, mat, o);
    EnergyOptions eo{StrainMeasure::GreenHalf, 0.0, 0.5, {}, {}};
    eo.stabilizer_fit = StabilizerFit::Quadratic;
    test::expect_stabiliser_derivatives<PointPrimitiveEnergy>(disc, eo);

    const PointPrimitiveEnergy energy(disc, eo);
    const Vec3Array x = test::large_deformation(disc.rest_positions(), 3);
    EnergyHessian H(energy);
    H.assemble(x);
    Vec3Array v(x.size()), Hv;
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = kDelta * Vec3(std::sin(1.0 + i), std::cos(2.0 * i), std::sin(0.3 * i));
    energy.hessian_product(x, v, Hv);
    const Eigen::Map<const Eigen::VectorXd> vv(v[0].data(), 3 * static_cast<Eigen::Index>(v.size()));
    const Eigen::VectorXd assembled = H.matrix() * vv;
    double err = 0.0, scale = 0.0;
    for (std::size_t i = 0; i < v.size(); ++i) {
      err = std::max(err, (assembled.segment<3>(3 * static_cast<Eigen::Index>(i)) - Hv[i]).norm());
      scale = std::max(scale, Hv[i].norm());
    }
    EXPECT_LE(err, 1e-10 * scale) << "basis " << static_cast<int>(basis);
  }
}

// The key: a curvature basis and a wall support are needed, and the Simpson volumes (which would integrate across the
// wall a second time) are refused with it; with a tube and the wall-quadratic basis it parses, its volume default
// the tet partition. quasi_static's default on a tube is the quadratic basis with Gauss points and the thickness
// reach, implicit's the linear basis at the nodes.
TEST(WallGaussPoints, AreCheckedAtTheirKey) {
  nlohmann::json doc = nlohmann::json::parse(R"({
    "name": "q", "model": "quasi_static",
    "geometry": { "type": "tube", "outer_radius_m": 0.0015, "wall_thickness_m": 0.0003, "length_m": 0.004,
                  "node_spacing_m": 0.0004 },
    "material": { "youngs_modulus_pa": 1e5, "poisson_ratio": 0.45, "density_kg_m3": 1060 },
    "discretization": { "wall_quadrature": "gauss", "basis": "linear" },
    "regions": [ { "name": "base", "select": { "type": "box", "max_m": [1, 1, 0] }, "bc": { "type": "fixed" } } ]
  })");
  std::string m = test::scene_error(doc, "q.json");
  EXPECT_NE(m.find("discretization.wall_quadrature"), std::string::npos) << m;
  EXPECT_NE(m.find("basis"), std::string::npos) << m;

  doc["discretization"].erase("wall_quadrature");
  doc["discretization"].erase("basis");
  Scene scene = parse_scene(doc, "q.json");
  EXPECT_EQ(scene.discretization.basis, GradientBasis::Quadratic);
  EXPECT_EQ(scene.discretization.wall_quadrature, DiscretizationOptions::WallQuadrature::Gauss);
  EXPECT_EQ(scene.discretization.wall_reach, DiscretizationOptions::WallReach::Thickness);
  EXPECT_EQ(scene.discretization.volume, VolumeRule::TetPartition);
  doc["model"] = "implicit";
  scene = parse_scene(doc, "q.json");
  EXPECT_EQ(scene.discretization.basis, GradientBasis::Linear);
  EXPECT_EQ(scene.discretization.wall_quadrature, DiscretizationOptions::WallQuadrature::Nodes);
  EXPECT_EQ(scene.discretization.wall_reach, DiscretizationOptions::WallReach::Layers);
  doc["model"] = "quasi_static";

  doc["discretization"]["wall_quadrature"] = "gauss";
  doc["discretization"]["basis"] = "wall_quadratic";
  scene = parse_scene(doc, "q.json");
  EXPECT_EQ(scene.discretization.volume, VolumeRule::TetPartition);
  EXPECT_EQ(scene.discretization.wall_quadrature, DiscretizationOptions::WallQuadrature::Gauss);

  doc["discretization"]["volume"] = "simpson";
  m = test::scene_error(doc, "q.json");
  EXPECT_NE(m.find("discretization.volume"), std::string::npos) << m;

  doc["discretization"].erase("volume");
  doc["discretization"]["basis"] = "quadratic";
  doc["discretization"]["support"] = "isotropic";
  m = test::scene_error(doc, "q.json");
  EXPECT_NE(m.find("discretization.wall_quadrature"), std::string::npos) << m;
  EXPECT_NE(m.find("support"), std::string::npos) << m;
}

}  // namespace
}  // namespace vascsim
