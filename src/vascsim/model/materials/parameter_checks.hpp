#pragma once
// Validation of hyperelastic-law parameters. Every check throws InputError with a message that names the
// law, the parameter (its JSON key), the value and the allowed range, e.g.
//   "hyperelastic law 'hgo': k2 = -1 must be >= 0".
// NaN and infinite values are always rejected.

#include <string_view>

namespace vascsim::materials {

/// value > 0.
void require_positive(std::string_view law, std::string_view key, double value);
/// value >= 0.
void require_non_negative(std::string_view law, std::string_view key, double value);
/// lo < value < hi (open interval).
void require_open_range(std::string_view law, std::string_view key, double value, double lo, double hi);
/// lo <= value <= hi (closed interval).
void require_closed_range(std::string_view law, std::string_view key, double value, double lo, double hi);

/// Lame constants of isotropic linear elasticity from Young's modulus E (Pa) and Poisson's ratio nu (-)
/// (docs/model/01-notation.md), after checking E > 0 and -1 < nu < 0.5 (keys "youngs_modulus_pa",
/// "poisson_ratio").
struct LameConstants {
  double lambda = 0.0;  ///< Pa
  double mu = 0.0;      ///< shear modulus, Pa
};
LameConstants checked_lame_constants(std::string_view law, double youngs_modulus_pa, double poisson_ratio);

}  // namespace vascsim::materials
