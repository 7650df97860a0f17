#pragma once
// Whether a tool's contact is wide enough for the lattice to resolve (docs/validation.md, "The contact's
// onset"): at its first tenths of a millimetre a rounded tool meets the wall in a Hertz contact, and while
// that contact spans less than about one and a half node spacings the force depends on where the nodes fall,
// by up to 4-6 % at one spacing. A run warns where it did.

#include <optional>
#include <string>

namespace vascsim {

/// Diameter 2a of the Hertz contact of a rigid sphere of radius `tip_radius_m` pressed with `force_n` into an
/// elastic half-space of Young's modulus `youngs_pa` and Poisson ratio `poisson`: a = (3 F R / (4 E*))^(1/3),
/// E* = E / (1 - nu^2), m. 0 for a force <= 0.
double hertz_contact_diameter_m(double force_n, double tip_radius_m, double youngs_pa, double poisson);

/// The contact is resolved from this many node spacings across on (the measured phase effect is within 1-2
/// points from about 1.4, 4-6 points at 1).
constexpr double kResolvedContactSpacings = 1.4;

/// Follows one tool through a run's load steps and remembers the deepest one whose contact was narrower than
/// kResolvedContactSpacings node spacings.
class ContactResolution {
 public:
  ContactResolution(std::string tool, double tip_radius_m, double youngs_pa, double poisson,
                    double node_spacing_m);
  /// One load step: the tool's displacement (m) and the force it exerts along its motion (N).
  void add(double displacement_m, double force_n);
  /// The node spacing along the wall that would have resolved every loaded step's contact so far: the
  /// narrowest Hertz diameter over kResolvedContactSpacings, m (0 before the tool carries a load).
  double resolving_spacing_m() const;
  /// One line if some step's contact was under-resolved, naming the depth up to which it was and the spacing
  /// that would resolve it.
  std::optional<std::string> warning() const;

 private:
  std::string tool_;
  double radius_m_, youngs_pa_, poisson_, spacing_m_;
  double depth_m_ = -1.0, diameter_m_ = 0.0;  // the deepest under-resolved step
  double narrowest_m_ = 0.0;                  // the smallest Hertz diameter of a loaded step
};

}  // namespace vascsim
