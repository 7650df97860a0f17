#pragma once
// Measurements of docs/validation.md T11 on a built MLS map: partition of unity, linear reproduction, and
// affine and rigid nodal fields reproduced at the surface in double and float32. Used by the unit
// tests and by `vascsim validate mls` (per-vessel tables in docs/validation.md).

#include <cstdint>

#include "vascsim/mapping/mls_map.hpp"

namespace vascsim {

struct MlsT11 {
  double unity = 0.0;       ///< max over vertices of |sum phi - 1|
  double linear = 0.0;      ///< max |sum phi X_i - S_v| / Delta
  double affine = 0.0;      ///< max |x_s - (A S_v + t)| / Delta for x = A X + t (random A near I), double
  double rigid90 = 0.0;     ///< same for a 90 degree rotation + translation
  double rigid_rand = 0.0;  ///< same for a random rotation + translation
  double f32 = 0.0;         ///< worst of the three fields through the float32 path, / Delta
  double max_displacement = 0.0;  ///< largest nodal displacement of the three fields, / Delta
  /// f32 / (eps_float * max_displacement): the float32 error against the rounding of the float input
  /// u itself (eps_float |u| is the spacing of floats at |u|; the map cannot do better than ~0.5).
  double f32_over_input_rounding = 0.0;
  double max_cond = 0.0;  ///< largest cond(A^) accepted
  Index min_support = 0;  ///< smallest |S(X)|

  /// The T11 criteria: unity <= 1e-12, linear/affine/rigid <= 1e-10 Delta, cond <= 1e3, |S| >= 8, and
  /// float32 <= 1e-5 Delta or, for fields whose displacements exceed ~100 Delta (where rounding the
  /// float input alone exceeds 1e-5 Delta), float32 <= 8 eps_float max|u|.
  bool passes() const;
};

/// Measures T11 on `map` built over the rest nodes X (#N, m) with mean spacing delta (m). The random
/// fields come from `seed` (translations up to 5 Delta, affine entries I + U(-0.2, 0.2)).
MlsT11 measure_mls_t11(const MlsMap& map, const Vec3Array& X, double delta, std::uint64_t seed);

}  // namespace vascsim
