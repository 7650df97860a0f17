#include "vascsim/run/contact_resolution.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include <fmt/format.h>

namespace vascsim {

namespace {
double effective_modulus(double youngs_pa, double poisson) {
  return youngs_pa / (1.0 - poisson * poisson);
}
}  // namespace

double hertz_contact_diameter_m(double force_n, double tip_radius_m, double youngs_pa, double poisson) {
  if (!(force_n > 0.0) || !(tip_radius_m > 0.0) || !(youngs_pa > 0.0)) return 0.0;
  return 2.0 * std::cbrt(3.0 * force_n * tip_radius_m / (4.0 * effective_modulus(youngs_pa, poisson)));
}

double hertz_contact_force_n(double diameter_m, double tip_radius_m, double youngs_pa, double poisson) {
  const double a = 0.5 * diameter_m;
  return 4.0 * effective_modulus(youngs_pa, poisson) * a * a * a / (3.0 * tip_radius_m);
}

double spacing_under_tool_m(const RigidObstacle& tool, const Body& body) {
  if (!body.wall || body.wall->cells.empty() || body.cloud.positions.empty())
    return along_wall_spacing_m(body);
  const WallCoordinates& wall = *body.wall;
  const constraints::Capsule at_end = obstacle_at(tool, 1.0);
  std::size_t nearest = 0;
  double gap = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < body.cloud.positions.size(); ++i)
    if (const double g = obstacle_contact(at_end, body.cloud.positions[i]).value; g < gap)
      gap = g, nearest = i;
  // As along_wall_spacing_m and the graded supports measure a cell: at mid-wall, a cell at a vessel's end
  // being half a step long.
  const LatticeCell& c = wall.cells[nearest];
  const bool end = wall.s_m[nearest] <= c.s_lo_m || wall.s_m[nearest] >= c.s_hi_m;
  const double around =
      mean_node_radius_m(body) * (c.theta_hi_deg - c.theta_lo_deg) * std::numbers::pi / 180.0;
  const double along = (c.s_hi_m - c.s_lo_m) * (end ? 2.0 : 1.0);
  return std::sqrt(around * along);
}

ContactResolution::ContactResolution(std::string tool, double tip_radius_m, double youngs_pa, double poisson,
                                     double node_spacing_m)
    : tool_(std::move(tool)),
      radius_m_(tip_radius_m),
      youngs_pa_(youngs_pa),
      poisson_(poisson),
      spacing_m_(node_spacing_m) {}

ContactResolution::ContactResolution(const RigidObstacle& tool, const Material& material, const Body& body)
    : ContactResolution(tool.name, tool.radius_m, material.youngs_modulus_pa, material.poisson_ratio,
                        spacing_under_tool_m(tool, body)) {}

void ContactResolution::add(double displacement_m, double force_n) {
  const double d = hertz_contact_diameter_m(std::abs(force_n), radius_m_, youngs_pa_, poisson_);
  if (d > 0.0 && spacing_m_ > 0.0 && d < kResolvedContactSpacings * spacing_m_ && displacement_m > depth_m_) {
    depth_m_ = displacement_m;
    diameter_m_ = d;
  }
}

double ContactResolution::resolving_force_n() const {
  return hertz_contact_force_n(kResolvedContactSpacings * spacing_m_, radius_m_, youngs_pa_, poisson_);
}

std::optional<std::string> ContactResolution::warning() const {
  if (depth_m_ < 0.0) return std::nullopt;
  // A tool that does not move (displacement 0) is named without a depth.
  const std::string where = depth_m_ > 0.0 ? fmt::format(" up to {:.3g} mm of its push", depth_m_ * 1e3) : "";
  // Only the lattice's spacing under the tool is named, and the force from which it resolves the contact:
  // both are the lattice's and the tool's, the same whatever the load steps (a spacing that resolves "the
  // first loaded step" would change with them).
  return fmt::format(
      "the contact of the tool '{}' was narrower than the lattice resolves{}: its Hertz diameter "
      "2 (3 F R / (4 E*))^(1/3) is {:.3g} mm there, {:.2g} of the lattice's node spacings of {:.3g} mm along "
      "the "
      "wall under the tool. Below about {:.1f} spacings, i.e. below a force of {:.3g} mN on this tool, the "
      "force "
      "depends on where the nodes fall, by up to 4-6 % at one spacing (docs/validation.md, \"The contact's "
      "onset\"). That force falls with the cube of the spacing under the tool: half the spacing resolves the "
      "contact from an eighth of it (geometry.node_spacing_m, or geometry.refine round the tool)",
      tool_, where, diameter_m_ * 1e3, diameter_m_ / spacing_m_, spacing_m_ * 1e3, kResolvedContactSpacings,
      resolving_force_n() * 1e3);
}

}  // namespace vascsim
