#pragma once
// Linear-elastic constants of an isotropic material (docs/model/01-notation.md). Inputs E [Pa], nu [-], rho
// [kg/m^3].

#include <cmath>

namespace vascsim {

struct Material {
  double youngs_modulus_pa = 0.5e6;
  double poisson_ratio = 0.45;
  double density_kg_m3 = 1060.0;

  double lame_lambda() const {
    const double E = youngs_modulus_pa, nu = poisson_ratio;
    return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  }
  double shear_modulus() const { return youngs_modulus_pa / (2.0 * (1.0 + poisson_ratio)); }
  double bulk_modulus() const { return youngs_modulus_pa / (3.0 * (1.0 - 2.0 * poisson_ratio)); }
  /// P-wave modulus M_p = lambda + 2 mu, Pa.
  double p_wave_modulus() const { return lame_lambda() + 2.0 * shear_modulus(); }
  /// P-wave speed c_p = sqrt(M_p / rho), m/s.
  double p_wave_speed() const { return std::sqrt(p_wave_modulus() / density_kg_m3); }
};

}  // namespace vascsim
