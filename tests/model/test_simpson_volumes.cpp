// Simpson volumes (discretization.volume = simpson, geometry/lattice_quadrature, docs/model/04-volumes.md):
// the weights integrate cubics along a lattice's layers, and with the quadratic basis the nodal sum gives a
// bending field the continuum's energy, which the tet partition's trapezoid weights overestimate by half with
// three layers (the cause of the quadratic basis's stiffness measured in docs/validation.md).

#include <gtest/gtest.h>

#include <cmath>

#include "support/test_support.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/geometry/generators.hpp"
#include "vascsim/geometry/lattice_quadrature.hpp"
#include "vascsim/model/discretization.hpp"
#include "vascsim/model/point_primitive_energy.hpp"
#include "vascsim/run/body_builder.hpp"
#include "vascsim/scene/scene.hpp"

#include <nlohmann/json.hpp>

namespace vascsim {
namespace {

// Sum_k w_k x_k^p against 1 / (p + 1) on [0, 1]: exact to rounding (1e-14) for p <= 3 and n >= 3 (the
// trapezoid on 3 points misses x^2 by 0.04, so the comparison can fail).
TEST(SimpsonVolumes, WeightsIntegrateCubicsExactly) {
  for (int n = 3; n <= 10; ++n) {
    const std::vector<double> w = cubic_exact_weights(n);
    ASSERT_EQ(static_cast<int>(w.size()), n);
    for (int p = 0; p <= 3; ++p) {
      double sum = 0.0;
      for (int k = 0; k < n; ++k) sum += w[static_cast<std::size_t>(k)] * std::pow(k / double(n - 1), p);
      EXPECT_NEAR(sum, 1.0 / (p + 1), 1e-14) << n << " points, x^" << p;
    }
    for (double wk : w) EXPECT_GT(wk, 0.0);
  }
  const std::vector<double> two = cubic_exact_weights(2);
  EXPECT_EQ(two, (std::vector<double>{0.5, 0.5}));
  EXPECT_THROW(cubic_exact_weights(1), InputError);
}

// A plate 8 x 6 cells in plane, 2 cells (3 node layers) thick: the field u = a (-x z, 0, x^2 / 2), z from the
// mid-plane, is pure bending with curvature a: eps_xx = -a z and no other strain, so the continuum energy is
// 1/2 (lambda + 2 mu) a^2 A t^3 / 12. With the quadratic basis every node's gradient is exact (QuadraticBasis
// tests), so the nodal sum differs from it only by the quadrature through the thickness and by the Green
// strain's second-order term (relative ~ a L = 1e-6 here). Simpson: within 1e-4 (that term, with margin). The
// tet partition: sum w z^2 = t^3 / 8 instead of t^3 / 12, 1.5 times the energy (between 1.45 and 1.55).
TEST(SimpsonVolumes, QuadraticBasisGivesABendingFieldTheContinuumEnergy) {
  BoxSpec spec;
  spec.cells = Eigen::Vector3i(8, 6, 2);
  spec.max_m = spec.cells.cast<double>() * test::kDelta;
  const Body body = body_from_lattice(make_box(spec));
  const Material mat = test::tissue(1e5);
  DiscretizationOptions trapezoid;
  trapezoid.basis = GradientBasis::Quadratic;
  DiscretizationOptions simpson = trapezoid;
  simpson.volume = VolumeRule::Simpson;
  simpson.volume_factors = simpson_volume_factors(body);
  const Discretization with_simpson(body.cloud, mat, simpson);
  const Discretization with_trapezoid(body.cloud, mat, trapezoid);
  EXPECT_NEAR(with_simpson.total_volume(), with_trapezoid.total_volume(),
              1e-12 * with_trapezoid.total_volume());

  const double a = 1e-6 / test::kDelta;  // curvature, 1/m
  const double z_mid = 0.5 * spec.max_m.z();
  Vec3Array x(body.cloud.positions.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const Vec3& X = body.cloud.positions[i];
    x[i] = X + a * Vec3(-X.x() * (X.z() - z_mid), 0.0, 0.5 * X.x() * X.x());
  }
  const double t = spec.max_m.z();
  const double area = spec.max_m.x() * spec.max_m.y();
  const double continuum = 0.5 * mat.p_wave_modulus() * a * a * area * t * t * t / 12.0;
  const EnergyOptions energy{StrainMeasure::GreenHalf, 0.0, 0.0, {}, {}};
  const double e_simpson = PointPrimitiveEnergy(with_simpson, energy).energy(x).total();
  const double e_trapezoid = PointPrimitiveEnergy(with_trapezoid, energy).energy(x).total();
  std::printf("[ simpson ] bending energy / continuum: Simpson %.8f, tet partition %.6f\n",
              e_simpson / continuum, e_trapezoid / continuum);
  EXPECT_NEAR(e_simpson / continuum, 1.0, 1e-4);
  EXPECT_NEAR(e_trapezoid / continuum, 1.5, 0.05);
}

// Through a vessel wall only the layer index counts: on a tube with 3 layers the factors are Simpson's over
// the trapezoid's, 2/3 at either surface and 4/3 in the middle (exact ratios), whatever the node's angle or
// s.
TEST(SimpsonVolumes, FactorsFollowTheWallLayers) {
  GeometrySpec spec;
  spec.type = "tube";
  spec.tube.length_m = 3e-3;
  const Body body = build_body(spec);
  const std::vector<double> f = simpson_volume_factors(body);
  ASSERT_EQ(f.size(), body.cloud.positions.size());
  const WallCoordinates& w = *body.wall;
  int checked = 0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    const bool surface = w.on_inner(static_cast<Index>(i)) || w.on_outer(static_cast<Index>(i));
    EXPECT_NEAR(f[i], surface ? 2.0 / 3.0 : 4.0 / 3.0, 1e-12) << "node " << i;
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

// A cloud without layers (no box cells, no wall) has no Simpson rule: an error that names the key and the
// alternative, not a silent tet partition.
TEST(SimpsonVolumes, ABodyWithoutLayersIsRefused) {
  NodeCloud cloud = test::lattice(2);
  cloud.box_cells = Eigen::Vector3i::Zero();
  try {
    simpson_volume_factors(body_from_lattice(cloud));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("discretization.volume"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("tet_partition"), std::string::npos) << e.what();
  }
}

// The scene's default follows the basis: the quadratic basis gets Simpson volumes on a lattice, the linear
// one keeps the tet partition, an explicit choice wins, and Simpson on an imported mesh is refused at the
// key.
TEST(SimpsonVolumes, TheQuadraticBasisDefaultsToThemInAScene) {
  nlohmann::json doc = nlohmann::json::parse(R"({
    "name": "s", "model": "quasi_static",
    "geometry": { "type": "box", "min_m": [0, 0, 0], "max_m": [0.004, 0.004, 0.002], "node_spacing_m": 0.001 },
    "material": { "youngs_modulus_pa": 1e5, "poisson_ratio": 0.45, "density_kg_m3": 1060 },
    "discretization": { "basis": "quadratic" },
    "regions": [ { "name": "base", "select": { "type": "box", "max_m": [1, 1, 0] }, "bc": { "type": "fixed" } } ]
  })");
  EXPECT_EQ(parse_scene(doc, "s.json").discretization.volume, VolumeRule::Simpson);
  doc["discretization"]["volume"] = "tet_partition";
  EXPECT_EQ(parse_scene(doc, "s.json").discretization.volume, VolumeRule::TetPartition);
  doc["discretization"] = {{"basis", "linear"}};
  EXPECT_EQ(parse_scene(doc, "s.json").discretization.volume, VolumeRule::TetPartition);
  doc["geometry"] = {
      {"type", "mesh"}, {"file", "wall.stl"}, {"wall_thickness_m", 1e-3}, {"node_spacing_m", 1e-3}};
  doc["discretization"] = {{"volume", "simpson"}};
  try {
    parse_scene(doc, "s.json");
    FAIL() << "Simpson volumes on an imported mesh";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("discretization.volume"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vascsim
