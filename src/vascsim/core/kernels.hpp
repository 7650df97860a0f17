#pragma once
// Smoothing kernels of the paper.
//  - poly6 (Eq. 1, Mueller et al. 2004): weights of the point-primitive gradient operator.
//  - cubic spline (Eq. 37): the MLS surface-map weight, W_cs(s) of docs/model/20-mls-map.md.

#include <numbers>

namespace vascsim::kernels {

/// Eq. 1: W(r,h) = 315/(64 pi h^9) (h^2 - r^2)^3 for 0 <= r < h, else 0. Units 1/m^3;
/// integrates to one over R^3 (docs/model/02-kernels.md section 2.1).
inline double poly6(double r, double h) {
  if (r < 0.0 || r >= h) return 0.0;
  const double h2 = h * h;
  const double q = h2 - r * r;
  const double h9 = h2 * h2 * h2 * h2 * h;
  return 315.0 / (64.0 * std::numbers::pi * h9) * q * q * q;
}

/// Eq. 37 as printed, a function of the normalised distance s = r / r_support (dimensionless):
/// 2/3 - 4s^2 + 4s^3 (s <= 1/2); 4/3 - 4s + 4s^2 - 4/3 s^3 (1/2 < s <= 1); 0 beyond. C^2 at s = 1/2.
inline double cubic_spline(double s) {
  if (s < 0.0) s = -s;
  if (s <= 0.5) return 2.0 / 3.0 - 4.0 * s * s + 4.0 * s * s * s;
  if (s <= 1.0) {
    const double t = 1.0 - s;
    return 4.0 / 3.0 * t * t * t;
  }
  return 0.0;
}

/// Derivative dW_cs/ds of Eq. 37 (docs/model/20-mls-map.md).
inline double cubic_spline_derivative(double s) {
  if (s < 0.0) return -cubic_spline_derivative(-s);
  if (s <= 0.5) return -8.0 * s + 12.0 * s * s;
  if (s <= 1.0) {
    const double t = 1.0 - s;
    return -4.0 * t * t;
  }
  return 0.0;
}

/// Eq. 37 normalised in 3-D: (12/pi) / r_support^3 * W_cs(r / r_support) integrates to one, since
/// int_0^1 W_cs(s) s^2 ds = 1/48 [derived in docs/model/02-kernels.md section 2.2].
inline double cubic_spline_3d(double r, double support) {
  const double c = 12.0 / std::numbers::pi / (support * support * support);
  return c * cubic_spline(r / support);
}

}  // namespace vascsim::kernels
