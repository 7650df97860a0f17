// run/contact_resolution: the Hertz contact's diameter and the run's warning where a tool's contact spans
// fewer node spacings than the lattice resolves (docs/validation.md, "The contact's onset").

#include <gtest/gtest.h>

#include <cmath>

#include "vascsim/run/contact_resolution.hpp"

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
  // The first step's 2a = 1.01 mm over 1.4 spacings: 0.722 mm resolves every step, and the message says so.
  EXPECT_NEAR(coarse.resolving_spacing_m(), hertz_contact_diameter_m(force[0], R, E, nu) / 1.4, 1e-15);
  EXPECT_NE(w.find("at most 0.722 mm"), std::string::npos) << w;
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

}  // namespace
}  // namespace vascsim
