// The embedded contact's surface as the scene builds it (run/contact_surface_builder.hpp): with
// contact.shape_functions "quadratic" the wall's samples follow a displacement that bends along the vessel
// exactly, where the barycentric weights cut its chords; the shape functions stay a partition of unity.

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "vascsim/core/error.hpp"
#include "vascsim/run/simulation.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim {
namespace {

// A 4 mm piece of the vein's wall (outer radius 1.5 mm, wall 0.3 mm) at 0.3 mm with a tool beside it (so that
// the contact surface is built) and the given shape functions.
Scene wall_scene(const char* shape) {
  nlohmann::json doc = nlohmann::json::parse(R"({
    "name": "surface", "model": "quasi_static",
    "geometry": { "type": "tube", "outer_radius_m": 1.5e-3, "wall_thickness_m": 0.3e-3, "length_m": 4e-3,
                  "node_spacing_m": 0.3e-3 },
    "material": { "youngs_modulus_pa": 0.5e6, "poisson_ratio": 0.45, "density_kg_m3": 1060 },
    "discretization": { "max_growths": 10 },
    "regions": [ { "name": "end", "select": { "type": "cylinder_end", "end": "start" }, "bc": { "type": "fixed" } } ],
    "obstacles": [ { "name": "catheter", "shape": "catheter", "diameter_fr": 6, "length_m": 5e-3,
                     "tip_m": [0, 3e-3, 2e-3], "direction": [0, -1, 0], "push_m": 0.1e-3 } ],
    "contact": { "surface": "embedded" },
    "quasi_static": { "load_steps": 1 }
  })");
  doc["contact"]["shape_functions"] = shape;
  return parse_scene(doc, "surface.json");
}

struct Misfit {
  double quadratic = 0.0;    // largest |sum_i phi_vi u_i - u(S_v)| over the samples with the fit, m
  double barycentric = 0.0;  // the same over the others on the walls' faces, m
};

// u_x = a (z - z0)^2 at every node: a field that bends along the vessel, quadratic in every sample's tangent
// coordinates (the axis z lies in every tangent plane of the tube). Returns the misfits at the samples and
// counts those with the fit (more than their triangle's three nodes).
Misfit misfit(const Simulation& sim, Index& quadratic_samples) {
  const ContactSurface& s = *sim.problem().contact_surface();
  const Vec3Array& X = sim.discretization().rest_positions();
  const double a = 1.0 / 1e-3, z0 = 2e-3;  // 1 mm of u_x per mm^2 of (z - z0)^2: 0.09 mm over one spacing
  const auto u = [&](const Vec3& p) { return a * (p.z() - z0) * (p.z() - z0); };
  Misfit m;
  quadratic_samples = 0;
  for (Index v = 0; v < s.num_samples(); ++v) {
    double sum = 0.0, phi_sum = 0.0;
    const Index nodes = s.row_start[v + 1] - s.row_start[v];
    for (Index k = s.row_start[v]; k < s.row_start[v + 1]; ++k) {
      sum += s.val[static_cast<std::size_t>(k)] * u(X[s.col[static_cast<std::size_t>(k)]]);
      phi_sum += s.val[static_cast<std::size_t>(k)];
    }
    EXPECT_NEAR(phi_sum, 1.0, 1e-12) << "sample " << v;
    const double err = std::abs(sum - u(s.rest_points[v]));
    if (nodes > 3) {
      ++quadratic_samples;
      m.quadratic = std::max(m.quadratic, err);
    } else if (nodes == 3) {
      m.barycentric = std::max(m.barycentric, err);
    }
  }
  return m;
}

TEST(ContactSurfaceBuilder, QuadraticShapeFunctionsFollowABendAlongTheWallExactly) {
  Index with_fit = 0;
  const Simulation quadratic(wall_scene("quadratic"));
  const Misfit q = misfit(quadratic, with_fit);
  ASSERT_TRUE(quadratic.contact_surface_report());
  EXPECT_EQ(quadratic.contact_surface_report()->quadratic, with_fit);
  // The faces of both walls (outer and inner) but the end rims' triangles (creases) take the fit.
  EXPECT_GT(with_fit, quadratic.contact_surface_report()->samples / 2);
  // Exact but for round-off of the 6x6 fit on fields of 1 mm: 1e-12 m.
  EXPECT_LT(q.quadratic, 1e-12);
  Index none = 0;
  const Simulation linear(wall_scene("interpolated"));
  const Misfit l = misfit(linear, none);
  EXPECT_EQ(none, 0);
  // The chords' sag, a L^2 / 8 with L the cross-sections' 0.3 mm (the diagonals' projections along z): ~11
  // um.
  EXPECT_GT(l.barycentric, 5e-6);
}

}  // namespace
}  // namespace vascsim
