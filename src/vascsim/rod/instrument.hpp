#pragma once
// A flexible instrument as a scene describes it (docs/scene-format.md, "instrument"; docs/model/26-rod.md
// section 26.7): a guidewire or a catheter, its section and material, its shaped tip, its friction against
// the wall, and how the hand drives it at the access port (insertion along the port's axis, rotation about
// it). Presets for common devices carry sourced values; a scene's own keys override a preset's. SI units.

#include <string>
#include <vector>

#include "vascsim/core/json_reader.hpp"
#include "vascsim/rod/cosserat_rod.hpp"
#include "vascsim/rod/rod_feeder.hpp"
#include "vascsim/rod/rod_section.hpp"

namespace vascsim::rod {

enum class TipShape { Straight, Angled, J };

/// One knot of the hand's motion at the port: at `time_s`, `inserted_m` of the rod past the port and the
/// proximal end turned by `twist_deg` about the port's axis; linear between knots, held after the last.
struct DriveKnot {
  double time_s = 0.0;
  double inserted_m = 0.0;
  double twist_deg = 0.0;
};

struct InstrumentSpec {
  std::string preset;  ///< the preset the values started from ("" for none)
  std::string name = "instrument";
  RodSection section;           ///< diameters (m), E and G (Pa)
  double density_kg_m3 = 0.0;   ///< of the section's material
  double length_m = 0.0;        ///< the distal length modelled (the rest stays outside the body), m
  double edge_length_m = 1e-3;  ///< the rod's discretisation along its length, m
  TipShape tip = TipShape::Straight;
  double tip_radius_m = 0.0;         ///< angled, J: the shaped arc's radius, m
  double tip_angle_deg = 0.0;        ///< angled, J: the arc's turn, deg
  double friction = 0.0;             ///< Coulomb's mu against the wall
  double port_s_m = 0.0;             ///< the access port's arc length along the vessel's centre-line, m
  double frame_s = 0.01;             ///< the time between two equilibria, s
  std::vector<DriveKnot> drive;      ///< the hand's motion; at least one knot
  double perforation_force_n = 0.0;  ///< a contact force above this on one node is flagged (0: none), N
};

/// The presets' names: "guidewire-035", "guidewire-014", "catheter-5fr-angled".
std::vector<std::string> instrument_presets();
/// A preset's values (its sources: docs/model/26-rod.md section 26.7). Throws InputError for an unknown name.
InstrumentSpec instrument_preset(const std::string& name);

/// Reads an "instrument" block: a preset (optional) and keys that override it; every value a preset does not
/// give is required. Throws InputError naming the key for a missing, unknown or out-of-range one.
InstrumentSpec read_instrument(JsonReader& block);

/// The hand's pose at `t_s` (inserted length in m, twist in rad), linear between the drive's knots.
std::pair<double, double> drive_at(const std::vector<DriveKnot>& drive, double t_s);

/// The instrument's rod at rest: its shaft straight from `base` along `axis`, the tip shaped towards `normal`
/// (unit, across the axis), edges of about edge_length_m.
CosseratRod make_instrument_rod(const InstrumentSpec& spec, const Vec3& base, const Vec3& axis,
                                const Vec3& normal);

}  // namespace vascsim::rod
