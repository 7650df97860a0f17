#pragma once
// Whether a tool's contact is wide enough for the lattice to resolve (docs/validation.md, "The contact's
// onset"): at its first tenths of a millimetre a rounded tool meets the wall in a Hertz contact, and while
// that contact spans less than about one and a half node spacings the force depends on where the nodes fall,
// by up to 4-6 % at one spacing. A run warns where it did, once per tool.

#include <optional>
#include <string>

#include "vascsim/geometry/vessel_body.hpp"
#include "vascsim/model/material.hpp"
#include "vascsim/model/rigid_obstacle.hpp"

namespace vascsim {

/// Diameter 2a of the Hertz contact of a rigid sphere of radius `tip_radius_m` pressed with `force_n` into an
/// elastic half-space of Young's modulus `youngs_pa` and Poisson ratio `poisson`: a = (3 F R / (4 E*))^(1/3),
/// E* = E / (1 - nu^2), m. 0 for a force <= 0.
double hertz_contact_diameter_m(double force_n, double tip_radius_m, double youngs_pa, double poisson);

/// The force of that contact at diameter `diameter_m`: F = 4 E* a^3 / (3 R), N (Hertz's law read backwards).
double hertz_contact_force_n(double diameter_m, double tip_radius_m, double youngs_pa, double poisson);

/// The contact is resolved from this many node spacings across on (the measured phase effect is within 1-2
/// points from about 1.4, 4-6 points at 1).
constexpr double kResolvedContactSpacings = 1.4;

/// The lattice's node spacing along the wall where `tool` meets it: the geometric mean of the steps around
/// and along the wall (at mid-wall) of the cell of the node nearest the tool at the end of its motion on a
/// graded lattice (geometry.refine), the lattice's one spacing on a uniform one (along_wall_spacing_m). The
/// spacing the contact sees: on a graded lattice the body's mean spacing is the coarse part's, far from the
/// tool. It depends on the lattice and the tool only, not on the load steps.
double spacing_under_tool_m(const RigidObstacle& tool, const Body& body);

/// Follows one tool through a run's load steps and remembers the deepest one whose contact was narrower than
/// kResolvedContactSpacings node spacings.
class ContactResolution {
 public:
  ContactResolution(std::string tool, double tip_radius_m, double youngs_pa, double poisson,
                    double node_spacing_m);
  /// `tool` on `body` (the spacing under it, spacing_under_tool_m), in a wall of `material` (its small-strain
  /// E, nu).
  ContactResolution(const RigidObstacle& tool, const Material& material, const Body& body);
  /// One load step: the tool's displacement (m) and the force it exerts along its motion (N).
  void add(double displacement_m, double force_n);
  /// The force from which the lattice resolves the tool's contact (its Hertz diameter is then
  /// kResolvedContactSpacings node spacings), N: a property of the lattice and the tool, not of the load
  /// steps.
  double resolving_force_n() const;
  /// One line if some step's contact was under-resolved, naming the depth up to which it was, the node
  /// spacing under the tool and the force from which that spacing resolves it.
  std::optional<std::string> warning() const;

 private:
  std::string tool_;
  double radius_m_, youngs_pa_, poisson_, spacing_m_;
  double depth_m_ = -1.0, diameter_m_ = 0.0;  // the deepest under-resolved step
};

}  // namespace vascsim
