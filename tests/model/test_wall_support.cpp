// Supports that follow the wall (discretization.support = wall, docs/model/03-neighbourhoods.md section 3.1):
// on a vessel lattice whose spacing along the wall is twice its layer spacing, each node's support is an
// ellipsoid, twice as long along the wall as through it, instead of a sphere grown until it holds enough
// in-plane neighbours.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

#include "vascsim/core/error.hpp"
#include "vascsim/run/discretization_setup.hpp"
#include "vascsim/run/simulation.hpp"
#include "vascsim/scene/scene.hpp"

#include "support/energy_checks.hpp"

namespace vascsim {
namespace {

// A 6 mm tube of the hand dorsal vein's wall (outer radius 1.5 mm, wall 0.3 mm: 3 layers 0.15 mm apart) with
// a spacing of 0.3 mm along the wall, ends clamped.
nlohmann::json tube(const std::string& support) {
  nlohmann::json doc = nlohmann::json::parse(R"({
    "name": "wall-tube", "model": "quasi_static",
    "geometry": { "type": "tube", "outer_radius_m": 1.5e-3, "wall_thickness_m": 0.3e-3, "length_m": 6e-3,
                  "node_spacing_m": 0.3e-3 },
    "material": { "youngs_modulus_pa": 5e5, "poisson_ratio": 0.45, "density_kg_m3": 1060 },
    "discretization": { "max_growths": 10, "basis": "linear" },
    "regions": [ { "name": "ends", "select": { "type": "box", "min_m": [-1, -1, -1], "max_m": [1, 1, 0] },
                   "bc": { "type": "fixed" } } ]
  })");
  doc["discretization"]["support"] = support;
  return doc;
}

// The isotropic rule (h = 2 x the mean nearest spacing, the 0.15 mm layer step) puts the in-plane neighbours,
// 0.3 mm away, on the edge of the support, so every node's support must grow (by 1.2 per step) until it holds
// enough of them, and it then reaches across the whole wall. The wall-aligned support holds them at once:
// only nodes at the tube's two ends (half neighbourhoods) grow, and every neighbour lies inside the node's
// ellipsoid, radius h_i through the wall and s h_i along it, s = the lattice's spacing along the wall over
// the layer step (about 2; the columns and cross-sections round it).
TEST(WallSupport, FollowsTheWallWithoutGrowing) {
  Simulation iso(parse_scene(tube("isotropic"), "tube.json"));
  Simulation wall(parse_scene(tube("wall"), "tube.json"));
  const Discretization& d = wall.discretization();
  const double stretch = discretization_options(wall.scene(), wall.body()).wall_stretch;
  EXPECT_NEAR(stretch, 2.0, 0.05);
  EXPECT_EQ(iso.discretization().grown_nodes(), iso.discretization().num_nodes());
  const Vec3Array& X = d.rest_positions();
  int grown_inside = 0;
  double worst = 0.0;  // max over pairs of the ellipsoidal distance / h_i
  for (Index i = 0; i < d.num_nodes(); ++i) {
    const double h = d.support_radius()[static_cast<std::size_t>(i)];
    const bool at_an_end = X[i].z() < 0.6e-3 || X[i].z() > 5.4e-3;
    if (h > 0.3e-3 * (1 + 1e-12) && !at_an_end) ++grown_inside;
    for (Index e = d.pairs().row_start[i]; e < d.pairs().row_start[i + 1]; ++e) {
      const Vec3& Xj = X[d.pairs().col[e]];
      const Vec3 Xij = Xj - X[i];
      const double across = std::hypot(Xj.x(), Xj.y()) - std::hypot(X[i].x(), X[i].y());  // depth difference
      worst = std::max(
          worst,
          std::sqrt(across * across + (Xij.squaredNorm() - across * across) / (stretch * stretch)) / h);
    }
  }
  std::printf(
      "[ wall support ] %.1f neighbours (isotropic %.1f); %d of %d nodes grown (isotropic: all); "
      "largest distance in the support %.6f h\n",
      d.mean_neighbours(), iso.discretization().mean_neighbours(), d.grown_nodes(), d.num_nodes(), worst);
  EXPECT_EQ(grown_inside, 0);
  EXPECT_LT(worst, 1.0);
}

// The gradient stays exact for affine fields (the patch test, T2: any positive weights in A_i and in the
// sum), at every node: 1e-10 relative, as PatchT2.
TEST(WallSupport, AffineFieldsGiveTheExactGradient) {
  Simulation wall(parse_scene(tube("wall"), "tube.json"));
  const Discretization& d = wall.discretization();
  Mat3 A;
  A << 0.1, -0.2, 0.05, 0.3, 0.02, -0.1, 0.07, 0.15, -0.04;
  EXPECT_LT(test::max_affine_gradient_error(d, A), 1e-10 * A.norm());
}

// On a curved wall the ellipsoid follows the layers, not the node's tangent plane: at 0.4 mm along the vein's
// wall (stretch 2.67, an ellipsoid 0.8 mm long on a wall of mid-radius 1.35 mm) a node's own layer curves
// away from its tangent plane by up to 0.24 mm, more than the 0.15 mm between layers. With the wall depths
// every node of the node's own layer within 0.9 of the in-plane reach is a neighbour (the depth difference is
// zero); measured with the tangent plane instead (no depths given), some are not, which shows the check can
// fail.
TEST(WallSupport, FollowsTheLayersOfACurvedWall) {
  nlohmann::json doc = tube("wall");
  doc["geometry"]["node_spacing_m"] = 0.4e-3;
  Simulation sim(parse_scene(doc, "tube.json"));
  const Body& body = sim.body();
  DiscretizationOptions flat = discretization_options(sim.scene(), body);
  flat.wall_depths.clear();
  const Discretization layered_disc(body.cloud, sim.scene().material,
                                    discretization_options(sim.scene(), body));
  const Discretization flat_disc(body.cloud, sim.scene().material, flat);
  auto missing_same_layer = [&](const Discretization& d) {
    const Vec3Array& X = d.rest_positions();
    const std::vector<double>& depth = body.wall->depth_m;
    const double stretch = flat.wall_stretch;
    int missing = 0;
    for (Index i = 0; i < d.num_nodes(); ++i) {
      const double reach = 0.9 * stretch * d.support_radius()[static_cast<std::size_t>(i)];
      std::vector<Index> row(d.pairs().col.begin() + d.pairs().row_start[i],
                             d.pairs().col.begin() + d.pairs().row_start[i + 1]);
      for (Index j = 0; j < d.num_nodes(); ++j)
        if (j != i && std::abs(depth[j] - depth[i]) < 1e-12 && (X[j] - X[i]).norm() < reach &&
            !std::binary_search(row.begin(), row.end(), j))
          ++missing;
    }
    return missing;
  };
  const int layered = missing_same_layer(layered_disc), tangent = missing_same_layer(flat_disc);
  std::printf(
      "[ wall support ] stretch %.2f: same-layer nodes inside 0.9 of the reach left out: %d with the layers, "
      "%d with the tangent plane\n",
      flat.wall_stretch, layered, tangent);
  EXPECT_EQ(layered, 0);
  EXPECT_GT(tangent, 0);
}

// discretization.wall_reach = thickness (docs/model/03-neighbourhoods.md section 3.2): every node's support
// holds every layer of the wall, so the quadratic basis fits the through-wall square at the surfaces without
// growing any support inside the tube (the default reach puts the far layer on the support's edge, where the
// weight is zero: a surface node sees two layers, and its quadratic guard grows the support); the gradient
// stays exact for affine fields (1e-10, as AffineFieldsGiveTheExactGradient) and, with the quadratic basis,
// for quadratic fields (1e-9, as QuadraticBasis.QuadraticFieldsGiveTheExactGradientAtEveryNode) at every node
// away from the tube's ends.
TEST(WallSupport, AThicknessReachHoldsEveryLayer) {
  auto layers_seen = [](const Discretization& d, Index i) {
    std::vector<long> layers;
    for (Index e = d.pairs().row_start[i]; e < d.pairs().row_start[i + 1]; ++e) {
      const Vec3& Xj = d.rest_positions()[static_cast<std::size_t>(d.pairs().col[e])];
      layers.push_back(std::lround(std::hypot(Xj.x(), Xj.y()) / 0.15e-3));
    }
    layers.push_back(std::lround(std::hypot(d.rest_positions()[i].x(), d.rest_positions()[i].y()) / 0.15e-3));
    std::sort(layers.begin(), layers.end());
    return static_cast<int>(std::unique(layers.begin(), layers.end()) - layers.begin());
  };
  auto fewest_layers = [&](const Discretization& d) {
    int fewest = 3;
    for (Index i = 0; i < d.num_nodes(); ++i) fewest = std::min(fewest, layers_seen(d, i));
    return fewest;
  };
  nlohmann::json doc = tube("wall");
  doc["discretization"]["basis"] = "quadratic";
  doc["discretization"]["wall_reach"] = "layers";
  Simulation by_layers(parse_scene(doc, "tube.json"));
  doc["discretization"]["wall_reach"] = "thickness";
  Simulation by_thickness(parse_scene(doc, "tube.json"));
  const Discretization& d = by_thickness.discretization();
  const Vec3Array& X = d.rest_positions();
  Vec3Array affine(X.size()), quadratic(X.size());
  Mat3 A;
  A << 0.1, -0.2, 0.05, 0.3, 0.02, -0.1, 0.07, 0.15, -0.04;
  const auto quad_field = [&](const Vec3& p) {
    Vec3 q;
    q << p.x() * p.y(), p.z() * p.z(), p.x() * p.z();
    return Vec3(A * p + q / 1e-3);
  };
  for (std::size_t i = 0; i < X.size(); ++i) {
    affine[i] = A * X[i];
    quadratic[i] = quad_field(X[i]);
  }
  double err_affine = 0.0, err_quadratic = 0.0, scale = 0.0;
  int grown_inside = 0;
  for (Index i = 0; i < d.num_nodes(); ++i) {
    err_affine = std::max(err_affine, (d.displacement_gradient(i, affine) - A).norm());
    const Vec3& p = X[static_cast<std::size_t>(i)];
    if (p.z() < 0.6e-3 || p.z() > 5.4e-3) continue;
    if (d.support_radius()[static_cast<std::size_t>(i)] > 0.3e-3 * (1 + 1e-12)) ++grown_inside;
    Mat3 curvature;  // the gradient of the quadratic part, 1e3 / m
    curvature << p.y(), p.x(), 0.0, 0.0, 0.0, 2.0 * p.z(), p.z(), 0.0, p.x();
    const Mat3 exact = A + curvature / 1e-3;
    scale = std::max(scale, exact.norm());
    err_quadratic = std::max(err_quadratic, (d.displacement_gradient(i, quadratic) - exact).norm());
  }
  std::printf(
      "[ wall support ] through-wall scale %.3f; fewest layers in a support: %d (reach by layers: %d); "
      "%d supports grown inside the tube (by layers: %d of %d); gradient errors %.2g (affine), %.2g "
      "(quadratic)\n",
      d.wall_across_scale(), fewest_layers(d), fewest_layers(by_layers.discretization()), grown_inside,
      by_layers.discretization().grown_nodes(), d.num_nodes(), err_affine / A.norm(), err_quadratic / scale);
  EXPECT_NEAR(d.wall_across_scale(), 0.75, 0.01);  // h_0 = 2 x the 0.15 mm layer step = the 0.3 mm wall
  EXPECT_EQ(fewest_layers(d), 3);
  EXPECT_EQ(grown_inside, 0);
  EXPECT_LT(err_affine, 1e-10 * A.norm());
  EXPECT_LT(err_quadratic, 1e-9 * scale);

  doc["discretization"]["support"] = "isotropic";
  try {
    parse_scene(doc, "tube.json");
    FAIL() << "an isotropic support took wall_reach";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("discretization.wall_reach"), std::string::npos) << e.what();
  }
}

// A body without node layers through a wall refuses it at the key.
TEST(WallSupport, NeedsAWall) {
  nlohmann::json doc = tube("wall");
  doc["geometry"] = {
      {"type", "box"}, {"min_m", {0, 0, 0}}, {"max_m", {0.004, 0.004, 0.004}}, {"node_spacing_m", 0.001}};
  try {
    Simulation sim(parse_scene(doc, "box.json"));
    FAIL() << "a box took wall-aligned supports";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("discretization.support"), std::string::npos) << e.what();
  }
}

// The default follows the model and the geometry: wall supports for the equilibrium models on a walled
// lattice (quasi_static, implicit), isotropic for the other models, for bodies without wall layers and for
// the paper's formulation; an explicit key wins.
TEST(WallSupport, IsTheEquilibriumModelsDefaultOnAWall) {
  using Support = DiscretizationOptions::Support;
  auto support_of = [](nlohmann::json doc) { return parse_scene(doc, "tube.json").discretization.support; };
  nlohmann::json doc = tube("wall");
  doc["discretization"].erase("support");
  EXPECT_EQ(support_of(doc), Support::Wall);
  doc["model"] = "implicit";
  EXPECT_EQ(support_of(doc), Support::Wall);
  doc["model"] = "xpbd";
  EXPECT_EQ(support_of(doc), Support::Isotropic);
  doc["model"] = "quasi_static";
  doc["formulation"] = "paper_literal";
  EXPECT_EQ(support_of(doc), Support::Isotropic);
  doc.erase("formulation");
  doc["discretization"]["support"] = "isotropic";
  EXPECT_EQ(support_of(doc), Support::Isotropic);
  doc["discretization"].erase("support");
  doc["geometry"] = {
      {"type", "box"}, {"min_m", {0, 0, 0}}, {"max_m", {0.004, 0.004, 0.004}}, {"node_spacing_m", 0.001}};
  EXPECT_EQ(support_of(doc), Support::Isotropic);
}

}  // namespace
}  // namespace vascsim
