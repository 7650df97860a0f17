#include "vascsim/rod/instrument.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "vascsim/core/error.hpp"
#include "vascsim/rod/rod_shape.hpp"

namespace vascsim::rod {

namespace {

constexpr double kInch = 25.4e-3;  // m

double shear_from_poisson(double e, double nu) {
  return e / (2.0 * (1.0 + nu));
}

}  // namespace

std::vector<std::string> instrument_presets() {
  return {"guidewire-035", "guidewire-014", "catheter-5fr-angled"};
}

InstrumentSpec instrument_preset(const std::string& name) {
  // The values and their sources: docs/model/26-rod.md section 26.7. A "nominal" value is a typical one the
  // scene should set when it knows its device.
  InstrumentSpec s;
  s.preset = name;
  s.name = name;
  s.friction = 0.05;  // nominal: within the 0.02-0.1 of hydrophilic coatings
  s.edge_length_m = 1e-3;
  s.length_m = 0.2;
  if (name == "guidewire-035") {
    // A 0.035-inch stiff wire: the flexural modulus Harrison et al. (2011) measured for the Amplatz Super
    // Stiff, a stainless-steel wire (nu 0.3 and 7,900 kg/m^3 nominal); a J tip of 3 mm radius.
    s.section = {0.035 * kInch, 0.0, 60.3e9, shear_from_poisson(60.3e9, 0.3)};
    s.density_kg_m3 = 7900.0;
    s.tip = TipShape::J;
    s.tip_radius_m = 3e-3;
    s.tip_angle_deg = 180.0;
  } else if (name == "guidewire-014") {
    // A 0.014-inch wire as a solid nitinol shaft: the initial modulus measured on a superelastic nitinol
    // guidewire core, 48 GPa (nu 0.33 and 6,450 kg/m^3 nominal); an angled tip (45 deg over a 2 mm radius,
    // nominal: such tips are shaped by hand).
    s.section = {0.014 * kInch, 0.0, 48e9, shear_from_poisson(48e9, 0.33)};
    s.density_kg_m3 = 6450.0;
    s.tip = TipShape::Angled;
    s.tip_radius_m = 2e-3;
    s.tip_angle_deg = 45.0;
  } else if (name == "catheter-5fr-angled") {
    // A 5 Fr tube (outer diameter 5/3 mm by the French scale) with a 0.038-inch lumen for a 0.035-inch wire,
    // of Pebax 72D, the stiffest of the Pebax 33 series (flexural modulus about 500 MPa; nu 0.45 and
    // 1,010 kg/m^3 nominal), without the braid that stiffens some shafts; an angled tip (45 deg over 5 mm).
    s.section = {5e-3 / 3.0, 0.038 * kInch, 0.5e9, shear_from_poisson(0.5e9, 0.45)};
    s.density_kg_m3 = 1010.0;
    s.tip = TipShape::Angled;
    s.tip_radius_m = 5e-3;
    s.tip_angle_deg = 45.0;
  } else {
    std::string known;
    for (const auto& p : instrument_presets()) known += (known.empty() ? "" : ", ") + p;
    throw InputError(fmt::format("instrument: unknown preset '{}'; known: {}", name, known));
  }
  return s;
}

namespace {

std::vector<DriveKnot> read_drive(JsonReader& b) {
  const nlohmann::json* d = b.raw("drive");
  const std::string what =
      "an array of [time_s, inserted_m, twist_deg] knots is required (the inserted length past the access "
      "port "
      "and the turn of the proximal end, linear between knots)";
  if (d == nullptr) b.missing("drive", what);
  if (!d->is_array() || d->empty()) b.fail("drive", what);
  std::vector<DriveKnot> knots;
  for (std::size_t k = 0; k < d->size(); ++k) {
    const nlohmann::json& e = (*d)[k];
    bool ok = e.is_array() && e.size() == 3;
    for (std::size_t c = 0; ok && c < 3; ++c) ok = e[c].is_number() && std::isfinite(e[c].get<double>());
    if (!ok)
      b.fail("drive",
             fmt::format("knot {} is {}; each knot is [time_s, inserted_m, twist_deg], three numbers", k,
                         e.dump()));
    const DriveKnot knot{e[0].get<double>(), e[1].get<double>(), e[2].get<double>()};
    if (knot.time_s < 0.0 || (!knots.empty() && !(knot.time_s > knots.back().time_s)))
      b.fail("drive",
             fmt::format("knot {}: time {} s; times start at 0 or later and increase", k, knot.time_s));
    if (!(knot.inserted_m > 0.0))
      b.fail("drive",
             fmt::format("knot {}: inserted length {} m; it must be positive (the rod past the port)", k,
                         knot.inserted_m));
    knots.push_back(knot);
  }
  return knots;
}

// A number the preset may give: required when there is no preset.
double value(JsonReader& b, bool preset, const std::string& key, double fallback, double lo, double hi) {
  return preset ? b.number(key, fallback, lo, hi) : b.required_number(key, lo, hi);
}

}  // namespace

InstrumentSpec read_instrument(JsonReader& b) {
  // "preset" is listed as allowed without one; inner_diameter_m, read after outer_diameter_m, is not that key
  // misspelt.
  b.allow({"preset", "inner_diameter_m"});
  const bool preset = b.has("preset");
  InstrumentSpec s =
      preset ? instrument_preset(b.string("preset", "", instrument_presets())) : InstrumentSpec{};
  s.name = b.string("name", s.name);
  s.section.outer_diameter_m = value(b, preset, "outer_diameter_m", s.section.outer_diameter_m, 1e-5, 0.02);
  s.section.inner_diameter_m =
      b.number("inner_diameter_m", preset ? s.section.inner_diameter_m : 0.0, 0.0, 0.02);
  if (!(s.section.inner_diameter_m < s.section.outer_diameter_m))
    b.fail("inner_diameter_m", fmt::format("{} m must be less than the outer diameter, {} m",
                                           s.section.inner_diameter_m, s.section.outer_diameter_m));
  const double e_preset = s.section.youngs_modulus_pa;
  s.section.youngs_modulus_pa = value(b, preset, "youngs_modulus_pa", e_preset, 1e3, 1e13);
  // G from the scene, else from its Poisson ratio, else the preset's ratio G / E with the scene's E.
  if (b.has("shear_modulus_pa") && b.has("poisson_ratio"))
    b.fail("poisson_ratio", "give shear_modulus_pa or poisson_ratio, not both");
  if (b.has("shear_modulus_pa"))
    s.section.shear_modulus_pa = b.required_number("shear_modulus_pa", 1e3, 1e13);
  else if (b.has("poisson_ratio") || !preset)
    s.section.shear_modulus_pa =
        shear_from_poisson(s.section.youngs_modulus_pa, b.required_number("poisson_ratio", -0.99, 0.5));
  else
    s.section.shear_modulus_pa *= s.section.youngs_modulus_pa / e_preset;
  b.allow({"shear_modulus_pa", "poisson_ratio"});
  s.density_kg_m3 = value(b, preset, "density_kg_m3", s.density_kg_m3, 1.0, 3e4);
  s.length_m = value(b, preset, "length_m", s.length_m, 1e-3, 10.0);
  s.edge_length_m = b.number("edge_length_m", s.edge_length_m, 1e-5, 0.1);
  if (s.edge_length_m > 0.5 * s.length_m)
    b.fail("edge_length_m",
           fmt::format("{} m is more than half the length, {} m", s.edge_length_m, s.length_m));
  JsonReader tip = b.object("tip");
  if (preset || b.has("tip")) {
    const std::string given = s.tip == TipShape::J ? "j" : s.tip == TipShape::Angled ? "angled" : "straight";
    const std::string shape = tip.string("shape", given, {"straight", "angled", "j"});
    s.tip = shape == "j" ? TipShape::J : shape == "angled" ? TipShape::Angled : TipShape::Straight;
    if (s.tip != TipShape::Straight) {
      s.tip_radius_m = tip.number("radius_m", s.tip_radius_m > 0.0 ? s.tip_radius_m : 3e-3, 1e-5, 1.0);
      s.tip_angle_deg = tip.number(
          "angle_deg", s.tip_angle_deg > 0.0 ? s.tip_angle_deg : (s.tip == TipShape::J ? 180.0 : 45.0), 1.0,
          270.0);
    } else {
      tip.allow({"radius_m", "angle_deg"});
    }
    tip.finish();
  }
  s.friction = b.number("friction", s.friction, 0.0, 2.0);
  s.port_s_m = b.number("port_s_m", 0.0, 0.0, 10.0);
  s.frame_s = b.number("frame_s", s.frame_s, 1e-4, 1.0);
  s.perforation_force_n = b.number("perforation_force_n", 0.0, 0.0, 100.0);
  s.drive = read_drive(b);
  for (const DriveKnot& k : s.drive)
    if (!(k.inserted_m < s.length_m - s.edge_length_m))
      b.fail("drive",
             fmt::format("an insertion of {} m leaves less than one edge of the {} m rod behind the port; "
                         "make length_m longer",
                         k.inserted_m, s.length_m));
  b.finish();
  return s;
}

std::pair<double, double> drive_at(const std::vector<DriveKnot>& drive, double t_s) {
  constexpr double kDeg = std::numbers::pi / 180.0;
  if (drive.empty()) return {0.0, 0.0};
  if (t_s <= drive.front().time_s) return {drive.front().inserted_m, drive.front().twist_deg * kDeg};
  for (std::size_t k = 1; k < drive.size(); ++k) {
    const DriveKnot &a = drive[k - 1], &b = drive[k];
    if (t_s <= b.time_s) {
      const double w = (t_s - a.time_s) / (b.time_s - a.time_s);
      return {a.inserted_m + w * (b.inserted_m - a.inserted_m),
              (a.twist_deg + w * (b.twist_deg - a.twist_deg)) * kDeg};
    }
  }
  return {drive.back().inserted_m, drive.back().twist_deg * kDeg};
}

CosseratRod make_instrument_rod(const InstrumentSpec& spec, const Vec3& base, const Vec3& axis,
                                const Vec3& normal) {
  const int edges = std::max(2, static_cast<int>(std::lround(spec.length_m / spec.edge_length_m)));
  const double angle = spec.tip == TipShape::Straight ? 0.0 : spec.tip_angle_deg * std::numbers::pi / 180.0;
  return CosseratRod(shaped_tip_rod(base, axis, normal, spec.length_m, edges, spec.tip_radius_m, angle),
                     rod_stiffness(spec.section));
}

}  // namespace vascsim::rod
