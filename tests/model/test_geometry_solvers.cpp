// Geometry generators, the conditioning guard, and the two solvers against each other and against
// global equilibrium.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

#include "support/run_helpers.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/experiments/cantilever.hpp"
#include "vascsim/geometry/boundary.hpp"
#include "vascsim/geometry/generators.hpp"
#include "vascsim/model/discretization.hpp"
#include "vascsim/run/simulation.hpp"
#include "vascsim/scene/scene.hpp"

namespace {

using namespace vascsim;

TEST(Geometry, TubeHasLayersOnBothSurfacesAndExactPolygonalVolume) {
  TubeSpec s;
  s.outer_radius_m = 1.5e-3;
  s.wall_thickness_m = 0.3e-3;
  s.length_m = 4e-3;
  s.node_spacing_m = 0.15e-3;
  const NodeCloud c = make_tube(s);
  ASSERT_TRUE(c.tube);
  EXPECT_GE(c.tube->radial_layers, 3);
  // Every node lies on one of the radial layers; inner and outer surfaces are layers.
  std::map<long, int> layers;
  for (const auto& p : c.positions) ++layers[std::lround(std::hypot(p.x(), p.y()) * 1e9)];
  EXPECT_EQ(static_cast<int>(layers.size()), c.tube->radial_layers);
  EXPECT_EQ(layers.begin()->first, std::lround(1.2e-3 * 1e9));
  EXPECT_EQ(layers.rbegin()->first, std::lround(1.5e-3 * 1e9));
  for (const Tet& t : c.tets)
    ASSERT_GT(signed_volume(c.positions[t[0]], c.positions[t[1]], c.positions[t[2]], c.positions[t[3]]), 0.0);
  // The tets fill the polygonal annulus exactly: (nt/2) sin(2 pi/nt) (R^2 - r^2) L; 1e-12 relative
  // (round-off only).
  const int per_ring = static_cast<int>(c.positions.size()) / c.tube->radial_layers /
                       (static_cast<int>(std::lround(s.length_m / s.node_spacing_m)) + 1);
  const double area =
      0.5 * per_ring * std::sin(2.0 * std::numbers::pi / per_ring) * (1.5e-3 * 1.5e-3 - 1.2e-3 * 1.2e-3);
  EXPECT_NEAR(vascsim::test::total_tet_volume(c), area * s.length_m, 1e-12 * area * s.length_m);
}

TEST(Geometry, TubeRejectsImpossibleWalls) {
  TubeSpec s;
  s.wall_thickness_m = s.outer_radius_m;
  EXPECT_THROW(make_tube(s), InputError);
}

TEST(Geometry, BoxBoundaryIsClosedWithTheBoxArea) {
  BoxSpec b;
  b.min_m = Vec3::Zero();
  b.max_m = Vec3(3.0, 2.0, 1.0);
  b.cells = Eigen::Vector3i(3, 2, 2);
  const NodeCloud c = make_box(b);
  EXPECT_EQ(c.tets.size(), 6u * 12u);
  EXPECT_NEAR(vascsim::test::total_tet_volume(c), 6.0, 1e-12);
  const auto faces = boundary_faces(c.tets);
  double area = 0.0;
  Vec3 vector_area = Vec3::Zero();
  std::map<std::pair<Index, Index>, int> edges;
  for (const auto& f : faces) {
    const Vec3 n = 0.5 * (c.positions[f[1]] - c.positions[f[0]]).cross(c.positions[f[2]] - c.positions[f[0]]);
    area += n.norm();
    vector_area += n;
    for (int e = 0; e < 3; ++e) ++edges[{std::min(f[e], f[(e + 1) % 3]), std::max(f[e], f[(e + 1) % 3])}];
    // Outward: the normal points away from the box centre.
    const Vec3 centroid = (c.positions[f[0]] + c.positions[f[1]] + c.positions[f[2]]) / 3.0;
    EXPECT_GT(n.dot(centroid - Vec3(1.5, 1.0, 0.5)), 0.0);
  }
  EXPECT_NEAR(area, 2.0 * (6.0 + 3.0 + 2.0), 1e-12);
  EXPECT_LT(vector_area.norm(), 1e-12);                         // a closed surface has zero vector area
  for (const auto& [edge, count] : edges) EXPECT_EQ(count, 2);  // watertight: every edge in two faces
}

// docs/validation.md T15 for the point-primitive operator: a single coplanar layer must be flagged, never
// silently inverted, and the message must name the node and its position.
TEST(Discretization, CoplanarCloudFailsLoudlyNamingTheNode) {
  NodeCloud c;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) c.positions.emplace_back(i * 1e-3, j * 1e-3, 0.0);
  try {
    Discretization d(c, Material{});
    FAIL() << "a coplanar cloud was accepted";
  } catch (const NumericalError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("node 0 at ("), std::string::npos) << m;
    EXPECT_NE(m.find("coplanar"), std::string::npos) << m;
  }
}

TEST(Discretization, TetPartitionVolumesSumToTheBodyAndSupportIsTwiceTheSpacing) {
  BoxSpec b;
  b.max_m = Vec3(4e-3, 4e-3, 4e-3);
  b.cells = Eigen::Vector3i(4, 4, 4);
  const Discretization d(make_box(b), Material{});
  EXPECT_NEAR(d.total_volume(), 64e-9, 1e-21);
  EXPECT_NEAR(d.mean_spacing(), 1e-3, 1e-15);
  EXPECT_NEAR(d.support_radius()[31], 2e-3, 1e-15);  // an interior node: no growth
  // Interior lattice nodes get Delta^3 (24 Kuhn tets of Delta^3/6, a quarter each). The Kuhn split is
  // not symmetric, so boundary nodes differ from the trapezoid rule: the origin corner sits on the
  // split diagonal of its cell (6 tets: Delta^3/4), the (4,0,0) corner is not (2 tets: Delta^3/12).
  EXPECT_NEAR(d.volumes()[31], 1e-9, 1e-21);
  EXPECT_NEAR(d.volumes()[0], 1e-9 / 4.0, 1e-21);
  EXPECT_NEAR(d.volumes()[4], 1e-9 / 12.0, 1e-21);
  // The transposed pair table holds the same pairs.
  EXPECT_EQ(d.pairs().col.size(), d.transposed().col.size());
}

// Static equilibrium of the whole body: the supports' reactions balance the applied loads, and the
// indenter's reaction is carried by the clamped ends. 1e-6 relative: the solve tolerance is 1e-8.
TEST(QuasiStatic, ReactionsBalanceOnAnIndentedTube) {
  nlohmann::json doc = {
      {"name", "small-indent"},
      {"geometry",
       {{"type", "tube"},
        {"outer_radius_m", 1.5e-3},
        {"wall_thickness_m", 0.5e-3},
        {"length_m", 4e-3},
        {"node_spacing_m", 0.25e-3}}},
      {"regions",
       {{{"name", "a"},
         {"select", {{"type", "cylinder_end"}, {"end", "start"}}},
         {"bc", {{"type", "fixed"}}}},
        {{"name", "b"}, {"select", {{"type", "cylinder_end"}, {"end", "end"}}}, {"bc", {{"type", "fixed"}}}},
        {{"name", "indenter"},
         {"select",
          {{"type", "wall_patch"},
           {"angle_center_deg", 90},
           {"angle_half_width_deg", 20},
           {"z_center_m", 2e-3},
           {"z_half_length_m", 0.6e-3}}},
         {"bc", {{"type", "displacement"}, {"direction", "inward"}, {"magnitude_m", 0.3e-3}}}}}},
      {"gravity_m_s2", {0.0, 0.0, -9.81}},
      {"quasi_static", {{"load_steps", 2}, {"rel_tolerance", 1e-8}}}};
  Simulation sim(parse_scene(doc, "test"));
  StepRecord r;
  for (int k = 1; k <= 2; ++k) r = sim.advance(k);
  ASSERT_TRUE(r.report.converged);
  const double weight = 9.81 * sim.discretization().total_volume() * 1060.0;
  const Vec3 total = r.regions[0].force_vector_n + r.regions[1].force_vector_n + r.regions[2].force_vector_n +
                     Vec3(0, 0, -weight);
  const double scale = r.regions[2].force_vector_n.norm();
  EXPECT_GT(r.regions[2].force_n, 0.0);  // the tissue resists the indenter
  EXPECT_LT(total.norm(), 1e-6 * scale);
  EXPECT_NEAR(r.regions[2].displacement_m, 0.3e-3, 1e-15);
}

// The meshless factor is rebuilt after a load step whose CG needed many iterations, for the next step: after
// the last one nothing follows, and the rebuild (15 of vein-indent's 92 s) is skipped. With
// refactor_cg_iterations 1 every step asks for one, so 3 load steps make 2 rebuilds, not 3.
TEST(QuasiStatic, NoRefactorisationAfterTheLastLoadStep) {
  nlohmann::json doc = {
      {"name", "small-indent"},
      {"geometry",
       {{"type", "tube"},
        {"outer_radius_m", 1.5e-3},
        {"wall_thickness_m", 0.5e-3},
        {"length_m", 4e-3},
        {"node_spacing_m", 0.25e-3}}},
      {"regions",
       {{{"name", "a"},
         {"select", {{"type", "cylinder_end"}, {"end", "start"}}},
         {"bc", {{"type", "fixed"}}}},
        {{"name", "b"}, {"select", {{"type", "cylinder_end"}, {"end", "end"}}}, {"bc", {{"type", "fixed"}}}},
        {{"name", "indenter"},
         {"select",
          {{"type", "wall_patch"},
           {"angle_center_deg", 90},
           {"angle_half_width_deg", 20},
           {"z_center_m", 2e-3},
           {"z_half_length_m", 0.6e-3}}},
         {"bc", {{"type", "displacement"}, {"direction", "inward"}, {"magnitude_m", 0.3e-3}}}}}},
      {"quasi_static",
       {{"load_steps", 3},
        {"rel_tolerance", 1e-8},
        {"preconditioner", "meshless"},
        {"refactor_cg_iterations", 1}}}};
  Simulation sim(parse_scene(doc, "test"));
  for (int k = 1; k <= 3; ++k) ASSERT_TRUE(sim.advance(k).report.converged);
  EXPECT_EQ(sim.model().info()["refactorisations"].get<int>(), 2);
}

// The explicit integrator relaxed to rest (mass-proportional damping) and the quasi-static solver
// find the same static tip deflection of a coarse cantilever. 1 %: the explicit run ends after
// ~15 damped first-mode periods, leaving < 0.1 % of the transient.
TEST(Explicit, DampedDynamicsSettlesOnTheQuasiStaticSolutionSlow) {
  CantileverCase c;
  c.cells_across = 2;
  nlohmann::json doc = cantilever_scene(c);
  const double quasi_static = run_cantilever(c).tip_deflection_m;
  doc["model"] = "explicit";
  doc["explicit"] = {
      {"duration_s", 1.5}, {"ramp_time_s", 0.2}, {"output_interval_s", 1.5}, {"damping_per_s", 30.0}};
  Simulation sim(parse_scene(doc, "test"));
  const StepRecord r = sim.advance(1);
  EXPECT_NEAR(r.regions[1].displacement_m / quasi_static, 1.0, 0.01);
}

}  // namespace
