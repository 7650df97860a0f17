#include "vascsim/run/contact_resolution.hpp"

#include <cmath>
#include <utility>

#include <fmt/format.h>

namespace vascsim {

double hertz_contact_diameter_m(double force_n, double tip_radius_m, double youngs_pa, double poisson) {
  if (!(force_n > 0.0) || !(tip_radius_m > 0.0) || !(youngs_pa > 0.0)) return 0.0;
  const double e_star = youngs_pa / (1.0 - poisson * poisson);
  return 2.0 * std::cbrt(3.0 * force_n * tip_radius_m / (4.0 * e_star));
}

ContactResolution::ContactResolution(std::string tool, double tip_radius_m, double youngs_pa, double poisson,
                                     double node_spacing_m)
    : tool_(std::move(tool)),
      radius_m_(tip_radius_m),
      youngs_pa_(youngs_pa),
      poisson_(poisson),
      spacing_m_(node_spacing_m) {}

void ContactResolution::add(double displacement_m, double force_n) {
  const double d = hertz_contact_diameter_m(std::abs(force_n), radius_m_, youngs_pa_, poisson_);
  if (d > 0.0 && (narrowest_m_ == 0.0 || d < narrowest_m_)) narrowest_m_ = d;
  if (d > 0.0 && spacing_m_ > 0.0 && d < kResolvedContactSpacings * spacing_m_ && displacement_m > depth_m_) {
    depth_m_ = displacement_m;
    diameter_m_ = d;
  }
}

double ContactResolution::resolving_spacing_m() const {
  return narrowest_m_ / kResolvedContactSpacings;
}

std::optional<std::string> ContactResolution::warning() const {
  if (depth_m_ < 0.0) return std::nullopt;
  // A tool that does not move (displacement 0) is named without a depth.
  const std::string where = depth_m_ > 0.0 ? fmt::format(" up to {:.3g} mm of its push", depth_m_ * 1e3) : "";
  return fmt::format(
      "the contact of the tool '{}' was narrower than the lattice resolves{}: its Hertz diameter "
      "2 (3 F R / (4 E*))^(1/3) is {:.3g} mm there, {:.2g} node spacings of {:.3g} mm; below about "
      "{:.1f} spacings the force depends on where the nodes fall, by up to 4-6 % at one spacing "
      "(docs/validation.md, \"The contact's onset\"). A node spacing of at most {:.3g} mm under the tool "
      "resolves it from the first loaded step (geometry.node_spacing_m, or geometry.refine round the tool)",
      tool_, where, diameter_m_ * 1e3, diameter_m_ / spacing_m_, spacing_m_ * 1e3, kResolvedContactSpacings,
      resolving_spacing_m() * 1e3);
}

}  // namespace vascsim
