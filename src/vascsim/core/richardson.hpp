#pragma once
// Richardson extrapolation of a sequence of resolutions and its uncertainty: the grid convergence index (GCI)
// procedure of Celik et al. 2008, "Procedure for estimation and reporting of uncertainty due to
// discretization in CFD applications", J. Fluids Eng. 130(7), 078001 (the same procedure
// validation/fem/richardson.py applies to the CalculiX references).
//
// Three resolutions h1 < h2 < h3 (fine to coarse) with values f1, f2, f3: the observed order p solves
//   p = |ln|e32/e21| + q(p)| / ln r21,  q(p) = ln((r21^p - s) / (r32^p - s)),  s = sign(e32/e21),
// with e21 = f2 - f1, e32 = f3 - f2, r21 = h2/h1, r32 = h3/h2 (a fixed-point iteration; q = 0 for a constant
// ratio); the extrapolated value is f_ext = (r21^p f1 - f2) / (r21^p - 1), and the fine resolution's relative
// error is bounded by GCI = 1.25 |(f1 - f2) / f1| / (r21^p - 1) (factor of safety 1.25 for three or more
// resolutions and an observed order).

#include <string>

namespace vascsim {

/// Why a sequence gives no extrapolation.
enum class RichardsonStatus {
  Extrapolated,    ///< monotone, with an order in the accepted range
  Exact,           ///< the three values agree to rounding: no discretisation error to estimate
  Oscillating,     ///< e32 / e21 < 0: the values go up and down with the resolution
  OrderOutOfRange  ///< monotone, but the observed order is below kMinObservedOrder or above kMaxObservedOrder
};

/// The name in reports: "extrapolated", "exact", "oscillating", "order out of range".
const char* richardson_status_name(RichardsonStatus status);

/// Observed orders outside [kMinObservedOrder, kMaxObservedOrder] mean the sequence is not in the asymptotic
/// range: below 0.5 the differences barely shrink (the extrapolation would reach far beyond the data), above
/// 6 they shrink faster than any consistent discretisation of second-order operators does (one value is off).
inline constexpr double kMinObservedOrder = 0.5;
inline constexpr double kMaxObservedOrder = 6.0;
/// Celik et al.'s factor of safety for three resolutions with an observed order.
inline constexpr double kGciSafetyFactor = 1.25;

struct Richardson {
  RichardsonStatus status = RichardsonStatus::Oscillating;
  double order = 0.0;         ///< observed order p (NaN when it has none)
  double extrapolated = 0.0;  ///< f_ext (Extrapolated), f1 (Exact); otherwise f1 as well
  /// (f1 - f_ext) / f_ext: the estimated relative error of the finest value (0 unless Extrapolated)
  double fine_error = 0.0;
  /// The GCI of the finest value: a bound on |relative error| with the factor of safety (0 unless
  /// Extrapolated)
  double fine_gci = 0.0;
};

/// Extrapolates three values f (fine to coarse) at the resolutions h (fine to coarse, increasing, > 0).
/// `scale` is the magnitude below which differences count as rounding (default: 1e-12 of max |f|).
Richardson richardson_extrapolate(const double (&h)[3], const double (&f)[3], double scale = 0.0);

/// The relative error of a value f at a resolution h, given the extrapolated value: (f - f_ext) / f_ext.
double relative_error(double f, double extrapolated);

/// The resolution (same unit as h) at which an error |error| at h, falling as h^order, becomes `target`
/// (|error| > 0, order > 0): h (target / |error|)^(1 / order).
double resolution_for_error(double h, double error, double order, double target);

}  // namespace vascsim
