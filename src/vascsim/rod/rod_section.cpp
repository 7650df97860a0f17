#include "vascsim/rod/rod_section.hpp"

#include <fmt/format.h>
#include <cmath>
#include <numbers>

#include "vascsim/core/error.hpp"

namespace vascsim::rod {

namespace {
constexpr double kPi = std::numbers::pi;
}

double RodSection::area_m2() const {
  return 0.25 * kPi * (outer_diameter_m * outer_diameter_m - inner_diameter_m * inner_diameter_m);
}

double RodSection::second_moment_m4() const {
  return kPi / 64.0 * (std::pow(outer_diameter_m, 4) - std::pow(inner_diameter_m, 4));
}

double RodSection::polar_moment_m4() const {
  return 2.0 * second_moment_m4();
}

double RodSection::shear_coefficient() const {
  const double nu = youngs_modulus_pa / (2.0 * shear_modulus_pa) - 1.0;
  return inner_diameter_m > 0.0 ? 2.0 * (1.0 + nu) / (4.0 + 3.0 * nu) : 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu);
}

RodStiffness rod_stiffness(const RodSection& s) {
  if (!(s.outer_diameter_m > 0.0) || !std::isfinite(s.outer_diameter_m))
    throw InputError(fmt::format("rod: outer diameter {} m must be positive", s.outer_diameter_m));
  if (!(s.inner_diameter_m >= 0.0) || !(s.inner_diameter_m < s.outer_diameter_m))
    throw InputError(fmt::format("rod: inner diameter {} m must be at least 0 and less than the outer {} m",
                                 s.inner_diameter_m, s.outer_diameter_m));
  if (!(s.youngs_modulus_pa > 0.0) || !std::isfinite(s.youngs_modulus_pa) || !(s.shear_modulus_pa > 0.0) ||
      !std::isfinite(s.shear_modulus_pa))
    throw InputError(fmt::format("rod: Young's modulus {} Pa and shear modulus {} Pa must be positive",
                                 s.youngs_modulus_pa, s.shear_modulus_pa));
  const double nu = s.youngs_modulus_pa / (2.0 * s.shear_modulus_pa) - 1.0;
  if (!(nu > -1.0 && nu < 0.5))
    throw InputError(fmt::format("rod: E {} Pa and G {} Pa give a Poisson ratio of {:.3g}, outside (-1, 0.5)",
                                 s.youngs_modulus_pa, s.shear_modulus_pa, nu));
  const double EI = s.youngs_modulus_pa * s.second_moment_m4();
  const double GJ = s.shear_modulus_pa * s.polar_moment_m4();
  const double kGA = s.shear_coefficient() * s.shear_modulus_pa * s.area_m2();
  const double EA = s.youngs_modulus_pa * s.area_m2();
  return RodStiffness{Vec3(EI, EI, GJ), Vec3(kGA, kGA, EA)};
}

}  // namespace vascsim::rod
