#pragma once
// Reference deflection of a cantilever with a tip load (the cantilever check T9, docs/validation.md):
// Euler-Bernoulli bending plus Timoshenko shear with Cowper's shear coefficient for a rectangular section,
//   delta_T = P L^3 / (3 E I) + P L / (kappa G A),   kappa = 10 (1 + nu) / (12 + 11 nu).

namespace vascsim {

/// Tip deflection (m) of a cantilever of length L (m) and rectangular section width b x height t (m),
/// bending in the direction of t, under tip load P (N), material E (Pa), nu.
inline double timoshenko_tip_deflection(double P, double L, double b, double t, double E, double nu) {
  const double I = b * t * t * t / 12.0;
  const double A = b * t;
  const double G = E / (2.0 * (1.0 + nu));
  const double kappa = 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu);
  return P * L * L * L / (3.0 * E * I) + P * L / (kappa * G * A);
}

}  // namespace vascsim
