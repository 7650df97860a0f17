// The integration constraint of the point-primitive quadrature (model/integration_constraint.hpp): c_k, the
// discrete divergence of node k's test function, is what a uniform stress turns into the force on node k
// (f_k = -sigma c_k), and where the quadrature is consistent it vanishes inside the body.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>

#include "support/test_support.hpp"
#include "vascsim/geometry/generators.hpp"
#include "vascsim/model/discretization.hpp"
#include "vascsim/model/integration_constraint.hpp"
#include "vascsim/model/point_primitive_energy.hpp"
#include "vascsim/run/simulation.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim {
namespace {

// A short piece of the vein with quasi_static's defaults on walls: quadratic fit through the whole wall,
// Gauss points over each node's cell, four node layers (1,568 nodes).
nlohmann::json vein_piece() {
  return nlohmann::json::parse(R"({
    "name": "vein-piece", "model": "quasi_static",
    "geometry": { "type": "vessel", "centerline": { "type": "straight", "length_m": 3e-3 },
                  "outer_radius_m": 1.5e-3, "wall_thickness_m": 0.3e-3, "node_spacing_m": 0.3e-3, "min_layers": 4 },
    "material": { "youngs_modulus_pa": 0.5e6, "poisson_ratio": 0.45, "density_kg_m3": 1060 },
    "regions": [ { "name": "end", "select": { "type": "cylinder_end", "end": "start" }, "bc": { "type": "fixed" } } ]
  })");
}

// c_k against the forces the energy itself computes under a uniform dilatation x = (1 + e) X: with SVK the
// first Piola-Kirchhoff stress is (1 + e)(3 lambda + 2 mu)(e + e^2 / 2) I everywhere (the stabiliser vanishes
// on affine fields), so f_k = -that * c_k exactly. The two are computed along different paths (the pair
// tables' gradient vectors and point offsets here; the energy's stress gather there), so they agree to
// rounding: 1e-9 of the largest force (measured 2e-12). The strain is 1e-3, not smaller: the fits reproduce
// an affine field to about 1e-10 in F, which at a strain of 1e-6 is already 1e-4 of it. Dropping the points'
// offsets from c_k (the gradient at the node only) misses the through-wall and along-wall derivatives and
// fails by O(1).
TEST(IntegrationConstraint, ResidualsAreTheForcesOfAUniformStress) {
  Simulation sim(parse_scene(vein_piece(), "vein-piece.json"));
  const Discretization& d = sim.discretization();
  ASSERT_EQ(d.energy_points(), 8);
  const double e = 1e-3, lambda = d.material().lame_lambda(), mu = d.material().shear_modulus();
  const double P = (1.0 + e) * (3.0 * lambda + 2.0 * mu) * (e + 0.5 * e * e);
  Vec3Array x(d.rest_positions());
  for (Vec3& p : x) p *= 1.0 + e;
  Vec3Array f;
  sim.energy().forces(x, f);
  const Vec3Array c = integration_residuals(d);
  double largest = 0.0, worst = 0.0;
  for (std::size_t k = 0; k < f.size(); ++k) {
    largest = std::max(largest, f[k].norm());
    worst = std::max(worst, (f[k] + P * c[k]).norm());
  }
  std::printf("[ integration constraint ] |f + P c| max %.3e of |f| max %.3e\n", worst, largest);
  ASSERT_GT(largest, 0.0);
  EXPECT_LT(worst, 1e-9 * largest);
}

// Inside a uniform lattice with the linear fit at the nodes every node's neighbourhood is symmetric, so
// d_ik = -d_ki and sum_j d_kj = 0 at every node whose neighbours' neighbourhoods are complete: c_k = 0 there
// to rounding (1e-12 of the boundary nodes' mean area; c_k on the boundary is of the order of that area).
// The report's interior is what the virtual tetrahedra's boundary faces leave: the lattice's inner nodes.
TEST(IntegrationConstraint, VanishesInsideAUniformLatticeWithTheLinearFit) {
  BoxSpec spec;
  const int cells = 10;
  spec.max_m = Vec3::Constant(cells * test::kDelta);
  spec.cells = Eigen::Vector3i::Constant(cells);
  const NodeCloud cloud = make_box(spec);
  const Discretization d(cloud, test::tissue(1e5));
  const IntegrationConstraintReport r = integration_constraint_report(d);
  EXPECT_EQ(r.interior_nodes, (cells - 1) * (cells - 1) * (cells - 1));
  const Vec3Array c = integration_residuals(d);
  double deep = 0.0, boundary = 0.0;
  const double lo = 4.5 * test::kDelta,
               hi = (cells - 4.5) * test::kDelta;  // beyond two supports (h = 2 spacings)
  for (std::size_t k = 0; k < c.size(); ++k) {
    const Vec3& p = cloud.positions[k];
    if (p.minCoeff() > lo && p.maxCoeff() < hi) deep = std::max(deep, c[k].norm());
    if (p.minCoeff() < 1e-12) boundary = std::max(boundary, c[k].norm());
  }
  std::printf("[ integration constraint ] deep interior %.3e, boundary %.3e, mean boundary area %.3e m^2\n",
              deep, boundary, r.boundary_area_m2);
  EXPECT_LT(deep, 1e-12 * r.boundary_area_m2);
  EXPECT_GT(boundary, 0.1 * r.boundary_area_m2);
}

}  // namespace
}  // namespace vascsim
