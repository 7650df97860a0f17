// A graded vessel lattice (geometry.refine): node positions along one axis (graded_axis), the swept wall
// built on them, its cells, its regions, and the point-primitive fit on it.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "vascsim/core/error.hpp"
#include "vascsim/geometry/centerline.hpp"
#include "vascsim/geometry/graded_axis.hpp"
#include "vascsim/geometry/swept_vessel.hpp"
#include "vascsim/geometry/vessel_body.hpp"
#include "vascsim/model/discretization.hpp"
#include "vascsim/model/point_primitive_energy.hpp"
#include "vascsim/run/body_builder.hpp"
#include "vascsim/run/discretization_setup.hpp"
#include "vascsim/run/simulation.hpp"
#include "vascsim/scene/scene.hpp"

#include "support/energy_checks.hpp"
#include "support/scene_errors.hpp"

namespace vascsim {
namespace {

bool contains(const std::vector<double>& x, double v) {
  return std::any_of(x.begin(), x.end(), [v](double p) { return std::abs(p - v) < 1e-12; });
}

// Along a 20 mm axis with a window of [8, 12] mm and 1 mm margins, fine 0.25 mm, coarse 1 mm, growth 1.3: the
// ends and every break are nodes, the window and margins have equal steps of 0.25 mm (their lengths are
// multiples of it), and outside each step is at most 1.3 times its neighbour nearer the window (the final
// scaling is one factor per side, so the ratio is exact up to the cap; next to the window the scaling itself
// enters, at most 10 % here) and never above the coarse spacing by more than that scaling.
TEST(GradedAxis, ALineIsFineInItsWindowAndGrowsOutside) {
  const AxisGrading g{0.25e-3, 1e-3, 1.3};
  const std::vector<double> x = graded_line(20e-3, {7e-3, 8e-3, 12e-3, 13e-3}, g);
  EXPECT_DOUBLE_EQ(x.front(), 0.0);
  EXPECT_DOUBLE_EQ(x.back(), 20e-3);
  for (double b : {7e-3, 8e-3, 12e-3, 13e-3}) EXPECT_TRUE(contains(x, b)) << b;
  for (std::size_t k = 0; k + 1 < x.size(); ++k) {
    const double step = x[k + 1] - x[k];
    ASSERT_GT(step, 0.0);
    const double mid = 0.5 * (x[k] + x[k + 1]);
    if (mid > 7e-3 && mid < 13e-3) {
      EXPECT_NEAR(step, 0.25e-3, 1e-12);
    } else {
      EXPECT_LT(step, 1.1e-3);
    }
    const double limit =
        1.3 * (std::abs(x[k] - 13e-3) < 1e-12 || std::abs(x[k + 1] - 7e-3) < 1e-12 ? 1.1 : 1.0 + 1e-9);
    if (k > 0 && mid > 13e-3) {
      EXPECT_LT(step / (x[k] - x[k - 1]), limit);
    }
    if (k + 2 < x.size() && mid < 7e-3) {
      EXPECT_LT(step / (x[k + 2] - x[k + 1]), limit);
    }
  }
  // Far fewer nodes than a uniform fine line (81).
  EXPECT_LT(x.size(), 45u);
}

// Around a closed axis the window comes first and the rest of the period is graded from both its edges: every
// value lies in [w0, w0 + period), the steps (including the one that closes the circle) are positive and at
// most the coarse spacing by the scaling, and the grading is symmetric about the point opposite the window's
// centre.
TEST(GradedAxis, ACircleClosesOntoItsWindow) {
  const AxisGrading g{0.2, 1.0, 1.25};
  const double period = 20.0;
  const std::vector<double> x = graded_circle(period, {-1.5, -1.0, 1.0, 1.5}, g);
  EXPECT_DOUBLE_EQ(x.front(), -1.5);
  for (double b : {-1.0, 1.0, 1.5}) EXPECT_TRUE(contains(x, b)) << b;
  std::vector<double> steps;
  for (std::size_t k = 0; k + 1 < x.size(); ++k) steps.push_back(x[k + 1] - x[k]);
  steps.push_back(x.front() + period - x.back());
  for (double s : steps) {
    EXPECT_GT(s, 0.0);
    EXPECT_LT(s, 1.1);
  }
  // Symmetry of the graded part: the k-th step after the window equals the k-th before it (the closing side).
  const std::size_t window_steps = static_cast<std::size_t>(
      std::find_if(x.begin(), x.end(), [](double v) { return std::abs(v - 1.5) < 1e-12; }) - x.begin());
  ASSERT_GT(steps.size(), window_steps + 2);
  for (std::size_t k = 0; k < (steps.size() - window_steps) / 2; ++k)
    EXPECT_NEAR(steps[window_steps + k], steps[steps.size() - 1 - k], 1e-12) << k;
}

TEST(GradedAxis, BadGradingIsAnInputError) {
  const AxisGrading ok{0.2, 1.0, 1.3};
  EXPECT_THROW(graded_line(10.0, {2.0, 3.0}, AxisGrading{0.0, 1.0, 1.3}), InputError);
  EXPECT_THROW(graded_line(10.0, {2.0, 3.0}, AxisGrading{2.0, 1.0, 1.3}), InputError);  // coarse below fine
  EXPECT_THROW(graded_line(10.0, {2.0, 3.0}, AxisGrading{0.2, 1.0, 1.0}), InputError);  // no growth
  EXPECT_THROW(graded_line(10.0, {3.0, 2.0}, ok), InputError);                          // decreasing
  EXPECT_THROW(graded_line(10.0, {11.0, 12.0}, ok), InputError);                        // off the axis
  EXPECT_THROW(graded_circle(4.0, {-2.5, 2.5}, ok), InputError);  // longer than the period
  // A margin of 0 repeats a break: accepted.
  EXPECT_NO_THROW(graded_line(10.0, {2.0, 2.0, 3.0, 3.0}, ok));
  EXPECT_NO_THROW(graded_circle(10.0, {2.0, 2.0, 3.0, 3.0}, ok));
}

// The bent aorta graded around its crown: the cells of the nodes on the outer wall tile it (their areas r
// d_theta ds, without the bend's stretch, sum to the straightened wall's 2 pi r L, which Pappus's rule makes
// the swept one's; a cell too short or too wide by half a step anywhere would miss by a few per cent), the
// refined window's edges are lattice lines, and the lattice has under 5,000 nodes (the uniform 1.5 mm lattice
// has about 20,000).
TEST(GradedLattice, TheCellsTileTheWallAndTheWindowEdgesAreLatticeLines) {
  const Centerline arch = bent_centerline(30e-3, 180.0, 10e-3);
  SweptVesselSpec spec;
  spec.outer_radius_m = 12.5e-3, spec.wall_thickness_m = 1.5e-3, spec.node_spacing_m = 4e-3,
  spec.min_layers = 4;
  spec.refine = {true, 180.0, 15.0, 0.5 * arch.length(), 5e-3, 1.5e-3, 3e-3, 1.3};
  const SweptVessel v = make_swept_vessel(arch, spec);
  const auto line = std::make_shared<const Centerline>(arch);
  const Body body = body_from_swept_vessel(v, line);
  const WallCoordinates& w = *body.wall;
  ASSERT_EQ(w.cells.size(), body.cloud.positions.size());
  EXPECT_TRUE(v.graded);
  EXPECT_LT(body.cloud.positions.size(), 5000u);
  // Edges: columns at 165 and 195 deg, cross-sections at L/2 -+ 5 mm.
  EXPECT_TRUE(std::any_of(v.theta_deg.begin(), v.theta_deg.end(),
                          [](double t) { return std::abs(t - 165.0) < 1e-9; }));
  EXPECT_TRUE(std::any_of(v.theta_deg.begin(), v.theta_deg.end(),
                          [](double t) { return std::abs(t - 195.0) < 1e-9; }));
  EXPECT_TRUE(contains(v.s_m, 0.5 * arch.length() - 5e-3));
  EXPECT_TRUE(contains(v.s_m, 0.5 * arch.length() + 5e-3));
  double area = 0.0, turn = 0.0;
  for (std::size_t i = 0; i < w.cells.size(); ++i) {
    if (!w.on_outer(static_cast<Index>(i))) continue;
    const LatticeCell& c = w.cells[i];
    EXPECT_LE(c.theta_lo_deg, 0.0);
    EXPECT_GE(c.theta_hi_deg, 0.0);
    EXPECT_LE(c.s_lo_m, w.s_m[i]);
    EXPECT_GE(c.s_hi_m, w.s_m[i]);
    area += spec.outer_radius_m * (c.theta_hi_deg - c.theta_lo_deg) * std::numbers::pi / 180.0 *
            (c.s_hi_m - c.s_lo_m);
    if (std::abs(w.s_m[i] - v.s_m[0]) < 1e-12) turn += c.theta_hi_deg - c.theta_lo_deg;
  }
  EXPECT_NEAR(turn, 360.0, 1e-9);
  EXPECT_NEAR(area / (2.0 * std::numbers::pi * spec.outer_radius_m * arch.length()), 1.0, 1e-12);
}

nlohmann::json graded_aorta() {
  return nlohmann::json::parse(R"({
    "name": "graded-aorta", "model": "quasi_static",
    "geometry": { "type": "vessel",
                  "centerline": { "type": "bent", "radius_of_curvature_m": 30e-3, "angle_deg": 180, "leg_length_m": 10e-3 },
                  "outer_radius_m": 12.5e-3, "wall_thickness_m": 1.5e-3, "node_spacing_m": 4e-3, "min_layers": 4,
                  "refine": { "angle_center_deg": 180, "angle_half_width_deg": 15, "s_center_fraction": 0.5,
                              "s_half_length_m": 5e-3, "node_spacing_m": 1.5e-3, "margin_m": 3e-3 } },
    "material": { "youngs_modulus_pa": 1e6, "poisson_ratio": 0.45, "density_kg_m3": 1060 },
    "discretization": { "max_growths": 10 },
    "regions": [
      { "name": "end_start", "select": { "type": "cylinder_end", "end": "start" }, "bc": { "type": "fixed" } },
      { "name": "end_finish", "select": { "type": "cylinder_end", "end": "end" }, "bc": { "type": "fixed" } },
      { "name": "indenter", "select": { "type": "wall_patch", "surface": "outer", "angle_center_deg": 180,
                                        "angle_half_width_deg": 15, "s_center_fraction": 0.5, "s_half_length_m": 5e-3 },
        "bc": { "type": "displacement", "direction": "inward", "magnitude_m": 1e-3 } } ]
  })");
}

// The patch test on the graded lattice: with quasi_static's defaults on walls (quadratic fit, per-node
// supports that follow the local spacing, Gauss points over each node's cell) every node's fitted gradient of
// an affine field is the field's own, to round-off: 1e-9 relative
// (WallSupport.AffineFieldsGiveTheExactGradient's 1e-10 on a tube 20 times smaller, whose supports are 4
// times less stretched; measured 1.7e-10 here), where a fit missing a term is wrong by O(1): the grading
// leaves the fit consistent. The patch selects the window, whose edges are nodes: 30 deg and 10 mm measured
// by its nodes' span.
TEST(GradedLattice, AffineFieldsGiveTheExactGradientAndThePatchIsTheWindow) {
  Simulation sim(parse_scene(graded_aorta(), "graded.json"));
  const Discretization& d = sim.discretization();
  Mat3 A;
  A << 0.1, -0.2, 0.05, 0.3, 0.02, -0.1, 0.07, 0.15, -0.04;
  EXPECT_LT(test::max_affine_gradient_error(d, A), 1e-9 * A.norm());
  const nlohmann::json report = sim.region_selections().at(2).report;
  EXPECT_NEAR(report.at("selected").at("angle_deg").get<double>(), 30.0, 1e-6);
  EXPECT_NEAR(report.at("selected").at("length_m").get<double>(), 10e-3, 1e-9);
}

// T3-T5 on the graded lattice, with the energy quasi_static builds from the scene (quadratic fit with the
// through-wall cube, per-node supports and cells, Gauss points over each cell, the quadratic stabiliser): a
// rigid motion stores no energy and moves no node, the forces at a large deformation conserve momentum, and
// the forces and Hessian product are the energy's derivatives (central differences). The bounds and their
// reasons are the shared checks' (support/energy_checks.hpp), which every basis and quadrature passes on a
// uniform lattice; a graded lattice must not loosen them, since its nodes differ only in their supports and
// cells.
TEST(GradedLattice, PassesTheEnergyChecksT3ToT5) {
  nlohmann::json doc = graded_aorta();  // coarser, for the finite differences: 1,836 nodes
  doc["geometry"]["node_spacing_m"] = 6e-3;
  doc["geometry"]["refine"]["node_spacing_m"] = 2.5e-3;
  doc["geometry"]["refine"]["margin_m"] = 2.5e-3;
  Simulation sim(parse_scene(doc, "graded.json"));
  ASSERT_FALSE(sim.body().wall->cells.empty());  // graded: every node has its own cell
  const PointPrimitiveEnergy& energy = sim.energy();
  ASSERT_GT(energy.options().stabilizer_alpha, 0.0);
  // A node's force scales with its own spacing squared: the bound's spacing is the lattice's largest, 6 mm.
  test::expect_rigid_motion_free_and_momentum(energy, sim.discretization().material(),
                                              doc["geometry"]["node_spacing_m"].get<double>());
  test::expect_stabiliser_derivatives<PointPrimitiveEnergy>(sim.discretization(), energy.options());
}

// A graded lattice's cells beside the fine window are long one way and short the other (here 4:1, 0.1 mm
// against 0.4 mm). Each node's support is stretched by its cell's own two sides, so it reaches two steps
// along either, as the quadratic fit needs, and the guard grows few supports: at most 2 % (measured none).
// With one stretch from the sides' mean, as before, the support reaches a single step along the long side,
// whose nodes then lie on its edge with no weight, and the guard grows the supports isotropically: asserted
// above 10 % (measured 16 %), which shows the check can fail.
TEST(GradedLattice, SupportsReachTwoStepsAlongBothSidesOfLongCells) {
  const nlohmann::json doc = nlohmann::json::parse(R"({
    "name": "graded-vein", "model": "quasi_static",
    "geometry": { "type": "vessel", "centerline": { "type": "straight", "length_m": 4e-3 },
                  "outer_radius_m": 1.5e-3, "wall_thickness_m": 0.3e-3, "node_spacing_m": 0.4e-3,
                  "refine": { "angle_center_deg": 90, "angle_half_width_deg": 30, "s_center_fraction": 0.5,
                              "s_half_length_m": 0.5e-3, "node_spacing_m": 0.1e-3, "margin_m": 0.2e-3 } },
    "material": { "youngs_modulus_pa": 0.5e6, "poisson_ratio": 0.45, "density_kg_m3": 1060 },
    "discretization": { "max_growths": 10 },
    "regions": [ { "name": "end", "select": { "type": "cylinder_end", "end": "start" },
                   "bc": { "type": "fixed" } } ]
  })");
  const Scene scene = parse_scene(doc, "graded-vein.json");
  const Body body = build_body(scene.geometry);
  const DiscretizationOptions sides = discretization_options(scene, body);
  ASSERT_EQ(sides.wall_axial_stretches.size(), body.cloud.positions.size());
  DiscretizationOptions mean = sides;
  for (std::size_t i = 0; i < mean.wall_stretches.size(); ++i)
    mean.wall_stretches[i] = std::sqrt(sides.wall_stretches[i] * sides.wall_axial_stretches[i]);
  mean.wall_axes.clear();
  mean.wall_axial_stretches.clear();
  const auto grown_share = [&](const DiscretizationOptions& o) {
    const Discretization d(body.cloud, scene.material, o);
    return static_cast<double>(d.grown_nodes()) / static_cast<double>(d.num_nodes());
  };
  const double with_sides = grown_share(sides), with_mean = grown_share(mean);
  std::printf("[ graded supports ] %zu nodes: grown %.3f with the cells' sides, %.3f with their mean\n",
              body.cloud.positions.size(), with_sides, with_mean);
  EXPECT_LT(with_sides, 0.02);
  EXPECT_GT(with_mean, 0.1);
}

// The centre-line point nearest a point: on the bent aorta's arch and on a leg, a point 12.5 mm out from the
// centre-line along any normal projects back to its own arc length (to 1e-9 m; golden-section search to 1e-12
// of the length, the rest round-off; the nearest sample alone is up to 0.13 mm off); past an end it projects
// to the end.
TEST(GradedLattice, ThePointNearestAToolProjectsOntoItsArcLength) {
  const Centerline arch = bent_centerline(30e-3, 180.0, 10e-3);
  for (double s : {3e-3, 10e-3, 0.37 * arch.length(), 0.5 * arch.length(), arch.length() - 4e-3})
    for (double angle_deg : {0.0, 90.0, 180.0, 250.0}) {
      const Frame f = arch.frame(s);
      const double a = angle_deg * std::numbers::pi / 180.0;
      const Vec3 p = arch.position(s) + 12.5e-3 * (std::cos(a) * f.N + std::sin(a) * f.B);
      EXPECT_NEAR(arch.closest_arc_length(p), s, 1e-9) << "s " << s << " angle " << angle_deg;
    }
  EXPECT_NEAR(arch.closest_arc_length(arch.position(0.0) - 5e-3 * arch.tangent(0.0)), 0.0, 1e-9);
  EXPECT_NEAR(arch.closest_arc_length(arch.position(arch.length()) + 5e-3 * arch.tangent(arch.length())),
              arch.length(), 1e-9);
}

// geometry.refine.around: the window centred on the probe at the arch's crown (its tip at 180 deg,
// mid-length) builds the lattice that the explicit centre does, node for node (1e-9 m: the projection's
// tolerance moves the window's centre by less), and the window turns with a tool moved round the vessel.
TEST(GradedLattice, AWindowAroundAToolIsCentredOnIt) {
  nlohmann::json explicit_centre = graded_aorta();
  explicit_centre["obstacles"] = nlohmann::json::parse(
      R"([{ "name": "probe", "shape": "catheter", "diameter_m": 10e-3, "length_m": 20e-3,
            "tip_m": [30e-3, 0, 52.5e-3], "direction": [0, 0, -1], "push_m": 1e-3 }])");
  explicit_centre["regions"].erase(2);
  nlohmann::json around = explicit_centre;
  for (const char* key : {"angle_center_deg", "s_center_fraction"}) around["geometry"]["refine"].erase(key);
  around["geometry"]["refine"]["around"] = "probe";
  auto largest_difference = [](const nlohmann::json& x, const nlohmann::json& y) {
    const Body a = build_body(parse_scene(x, "graded.json").geometry);
    const Body b = build_body(parse_scene(y, "graded.json").geometry);
    EXPECT_EQ(a.cloud.positions.size(), b.cloud.positions.size());
    double largest = a.cloud.positions.size() == b.cloud.positions.size() ? 0.0 : 1.0;
    for (std::size_t i = 0; i < std::min(a.cloud.positions.size(), b.cloud.positions.size()); ++i)
      largest = std::max(largest, (a.cloud.positions[i] - b.cloud.positions[i]).norm());
    return largest;
  };
  EXPECT_LT(largest_difference(explicit_centre, around), 1e-9);
  // The probe moved a quarter turn round the crown's cross-section, to the arch's side (+y, the frame's B
  // there: 90 deg): the window follows it, and differs from the crown's.
  nlohmann::json side = around, side_explicit = explicit_centre;
  for (nlohmann::json* doc : {&side, &side_explicit}) {
    (*doc)["obstacles"][0]["tip_m"] = {30e-3, 12.5e-3, 40e-3};
    (*doc)["obstacles"][0]["direction"] = {0, -1, 0};
  }
  side_explicit["geometry"]["refine"]["angle_center_deg"] = 90;
  EXPECT_LT(largest_difference(side_explicit, side), 1e-9);
  EXPECT_GT(largest_difference(explicit_centre, side), 1e-3);
}

TEST(GradedLattice, BadRefinementIsAnInputError) {
  auto fails = [](const nlohmann::json& doc, const char* what) {
    const std::string message = test::scene_error(doc, "graded.json");
    EXPECT_NE(message.find(what), std::string::npos) << message;
  };
  nlohmann::json coarser = graded_aorta();
  coarser["geometry"]["refine"]["node_spacing_m"] = 5e-3;
  fails(coarser, "coarser than geometry.node_spacing_m");
  nlohmann::json fitted = graded_aorta();
  fitted["geometry"]["fit_lattice_to_patch"] = "edges";
  fails(fitted, "fit_lattice_to_patch");
  nlohmann::json turned = graded_aorta();
  turned["geometry"]["lattice_angle_deg"] = 3.0;
  fails(turned, "lattice_angle_deg");
  nlohmann::json unknown = graded_aorta();
  unknown["geometry"]["refine"]["spacing"] = 1e-3;
  fails(unknown, "spacing");
  nlohmann::json tube = graded_aorta();
  tube["geometry"] = {
      {"type", "tube"},   {"outer_radius_m", 1.5e-3}, {"wall_thickness_m", 0.3e-3},
      {"length_m", 0.02}, {"node_spacing_m", 0.3e-3}, {"refine", graded_aorta()["geometry"]["refine"]}};
  fails(tube, "refine");
  nlohmann::json nobody = graded_aorta();
  nobody["geometry"]["refine"].erase("angle_center_deg");
  nobody["geometry"]["refine"].erase("s_center_fraction");
  nobody["geometry"]["refine"]["around"] = "probe";
  fails(nobody, "no obstacle named 'probe'");
  nlohmann::json both = graded_aorta();
  both["geometry"]["refine"]["around"] = "probe";
  fails(both, "leave it out");
}

}  // namespace
}  // namespace vascsim
