// run/contact_resolution: the Hertz contact's diameter and the run's warning where a tool's contact spans
// fewer node spacings than the lattice resolves (docs/validation.md, "The contact's onset").

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "vascsim/run/body_builder.hpp"
#include "vascsim/run/contact_resolution.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim {
namespace {

// Hertz's law read backwards: a sphere of radius R indenting a half-space with contact radius a carries
// F = 4 E* a^3 / (3 R). The aorta's probe at 0.25 mm (F = 43.23 mN, R = 5 mm, E = 1 MPa, nu = 0.45) has a =
// 0.51 mm.
TEST(ContactResolution, HertzDiameterInvertsHertzsLaw) {
  const double E = 1.0e6, nu = 0.45, R = 5e-3, F = 43.2312e-3;
  const double d = hertz_contact_diameter_m(F, R, E, nu);
  const double a = 0.5 * d, e_star = E / (1.0 - nu * nu);
  EXPECT_NEAR(4.0 * e_star * a * a * a / (3.0 * R), F, 1e-12 * F);  // a closed form: round-off only
  EXPECT_NEAR(d, 1.0113e-3, 1e-7);
  EXPECT_EQ(hertz_contact_diameter_m(0.0, R, E, nu), 0.0);
  EXPECT_EQ(hertz_contact_diameter_m(-1.0, R, E, nu), 0.0);
}

// The probe's steps against a 1.0 mm lattice: 2a = 1.01 / 1.28 / 1.45 mm at 0.25 / 0.5 / 0.75 mm, so the
// contact is under-resolved (below 1.4 spacings) to 0.5 mm and the warning names that depth; on a 0.5 mm
// lattice it never is.
TEST(ContactResolution, WarnsUpToTheDeepestUnderResolvedStep) {
  const double E = 1.0e6, nu = 0.45, R = 5e-3;
  const double depth[] = {0.25e-3, 0.5e-3, 0.75e-3}, force[] = {43.23e-3, 86.99e-3, 126.87e-3};
  ContactResolution coarse("probe", R, E, nu, 1.0e-3), fine("probe", R, E, nu, 0.5e-3);
  EXPECT_FALSE(coarse.warning().has_value());  // nothing seen yet
  for (int k = 0; k < 3; ++k) {
    coarse.add(depth[k], force[k]);
    fine.add(depth[k], force[k]);
  }
  ASSERT_TRUE(coarse.warning().has_value());
  const std::string w = *coarse.warning();
  EXPECT_NE(w.find("'probe'"), std::string::npos) << w;
  EXPECT_NE(w.find("up to 0.5 mm"), std::string::npos) << w;
  EXPECT_NE(w.find("1.28 mm"), std::string::npos) << w;
  // The 1.0 mm lattice resolves the probe's contact from 2a = 1.4 mm on: F = 4 E* (0.7 mm)^3 / (3 R) = 115
  // mN, the force the message names (the third step's 126.9 mN is above it).
  EXPECT_NEAR(coarse.resolving_force_n(), hertz_contact_force_n(1.4e-3, R, E, nu), 1e-15);
  EXPECT_NEAR(hertz_contact_diameter_m(coarse.resolving_force_n(), R, E, nu), 1.4e-3, 1e-15);
  EXPECT_NE(w.find("node spacings of 1 mm along the wall under the tool"), std::string::npos) << w;
  EXPECT_NE(w.find("below a force of 115 mN on this tool"), std::string::npos) << w;
  EXPECT_FALSE(fine.warning().has_value()) << *fine.warning();
  ContactResolution untouched("probe", R, E, nu, 1.0e-3);
  untouched.add(1e-3, 0.0);
  EXPECT_FALSE(untouched.warning().has_value());
  // A tool that does not move is named without a depth.
  ContactResolution fixed("wall_probe", R, E, nu, 1.0e-3);
  fixed.add(0.0, 43.23e-3);
  ASSERT_TRUE(fixed.warning().has_value());
  const std::string f = *fixed.warning();
  EXPECT_EQ(f.find("of its push"), std::string::npos) << f;
  EXPECT_NE(f.find("'wall_probe' was narrower than the lattice resolves: its Hertz"), std::string::npos) << f;
}

// One lattice and one tool, pressed along one force-depth curve (the probe's, about 170 mN per mm) in 3 or in
// 6 load steps: the warning names the same node spacing and the same force from which that spacing resolves
// the contact either way; only the depth up to which the steps were under-resolved follows the steps (0.5 and
// 0.625 mm). (It named the spacing that resolved the first loaded step instead: 0.718 mm with 3 steps, 0.570
// mm with 6.)
TEST(ContactResolution, TheWarningNamesTheSameSpacingWhateverTheLoadSteps) {
  const double E = 1.0e6, nu = 0.45, R = 5e-3, push = 0.75e-3;
  auto warning_with = [&](int steps) {
    ContactResolution r("probe", R, E, nu, 1.0e-3);
    for (int k = 1; k <= steps; ++k) r.add(push * k / steps, 170.0 * push * k / steps);
    return r.warning().value_or("");
  };
  const std::string three = warning_with(3), six = warning_with(6);
  EXPECT_NE(three.find("up to 0.5 mm"), std::string::npos) << three;
  EXPECT_NE(six.find("up to 0.625 mm"), std::string::npos) << six;
  // Everything from the spacing on is the lattice's and the tool's.
  const std::size_t a = three.find("of the lattice's node spacings"),
                    b = six.find("of the lattice's node spacings");
  ASSERT_NE(a, std::string::npos) << three;
  ASSERT_NE(b, std::string::npos) << six;
  EXPECT_EQ(three.substr(a), six.substr(b));
  EXPECT_NE(three.find("below a force of 115 mN"), std::string::npos) << three;
}

// The spacing a tool's contact sees on a graded lattice (a vein 0.1 mm over +-30 deg x +-0.5 mm facing +y at
// mid-length, 0.4 mm elsewhere): that of the cell under the tool, the fine one in the window (where the
// lattice's steps, its finest, say the same) and a coarse one on the far side 3 mm along, where the finest
// steps would call a contact resolved that is not.
TEST(ContactResolution, TheSpacingUnderAToolIsTheLatticesThere) {
  const nlohmann::json doc = nlohmann::json::parse(R"({
    "name": "graded-vein", "model": "quasi_static",
    "geometry": { "type": "vessel", "centerline": { "type": "straight", "length_m": 8e-3 },
                  "outer_radius_m": 1.5e-3, "wall_thickness_m": 0.3e-3, "node_spacing_m": 0.4e-3,
                  "refine": { "angle_center_deg": 90, "angle_half_width_deg": 30, "s_center_fraction": 0.5,
                              "s_half_length_m": 0.5e-3, "node_spacing_m": 0.1e-3, "margin_m": 0.2e-3 } },
    "regions": [ { "name": "end", "select": { "type": "cylinder_end", "end": "start" }, "bc": { "type": "fixed" } } ]
  })");
  const Body body = build_body(parse_scene(doc, "graded-vein.json").geometry);
  ASSERT_FALSE(body.wall->cells.empty());
  auto sphere_at = [](double y, double dy, double z = 4e-3) {
    RigidObstacle s;
    s.name = "probe";
    s.radius_m = 1e-3;
    s.a_m = s.b_m = s.tool_point_m = Vec3(0.0, y, z);
    s.motion_m = Vec3(0.0, dy, 0.0);
    return s;
  };
  const double finest = along_wall_spacing_m(body);
  const double window = spacing_under_tool_m(sphere_at(2.5e-3, -0.2e-3), body);
  const double far_side = spacing_under_tool_m(sphere_at(-2.5e-3, 0.2e-3, 7e-3), body);
  EXPECT_NEAR(window, finest, 0.05 * finest);
  EXPECT_NEAR(window, 0.1e-3, 0.02e-3);
  EXPECT_GT(far_side, 3.0 * window);
  EXPECT_LT(far_side, 0.5e-3);
  // A uniform lattice has one spacing.
  nlohmann::json uniform = doc;
  uniform["geometry"].erase("refine");
  const Body plain = build_body(parse_scene(uniform, "vein.json").geometry);
  EXPECT_EQ(spacing_under_tool_m(sphere_at(-2.5e-3, 0.2e-3), plain), along_wall_spacing_m(plain));
}

}  // namespace
}  // namespace vascsim
