#include "vascsim/core/richardson.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vascsim {

const char* richardson_status_name(RichardsonStatus status) {
  switch (status) {
    case RichardsonStatus::Extrapolated:
      return "extrapolated";
    case RichardsonStatus::Exact:
      return "exact";
    case RichardsonStatus::Oscillating:
      return "oscillating";
    case RichardsonStatus::OrderOutOfRange:
      return "order out of range";
  }
  return "?";
}

namespace {

// Celik et al.'s fixed-point iteration for p; NaN when it does not settle.
double observed_order(double r21, double r32, double ratio) {
  const double s = ratio > 0.0 ? 1.0 : -1.0;
  double p = std::abs(std::log(std::abs(ratio))) / std::log(r21);
  for (int i = 0; i < 500; ++i) {
    const double num = std::pow(r21, p) - s, den = std::pow(r32, p) - s;
    if (num <= 0.0 || den <= 0.0) return std::numeric_limits<double>::quiet_NaN();
    const double next = std::abs(std::log(std::abs(ratio)) + std::log(num / den)) / std::log(r21);
    if (!std::isfinite(next)) return std::numeric_limits<double>::quiet_NaN();
    if (std::abs(next - p) < 1e-12 * std::max(1.0, p)) return next;
    p = next;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

Richardson richardson_extrapolate(const double (&h)[3], const double (&f)[3], double scale) {
  Richardson r;
  r.order = std::numeric_limits<double>::quiet_NaN();
  r.extrapolated = f[0];
  if (scale <= 0.0) scale = 1e-12 * std::max({std::abs(f[0]), std::abs(f[1]), std::abs(f[2])});
  const double e21 = f[1] - f[0], e32 = f[2] - f[1];
  if (std::abs(e21) <= scale && std::abs(e32) <= scale) {
    r.status = RichardsonStatus::Exact;
    r.order = 0.0;
    return r;
  }
  if (std::abs(e21) <= scale ||
      e32 / e21 <= 0.0) {  // the finer pair agrees but the coarser not, or up and down
    r.status = RichardsonStatus::Oscillating;
    return r;
  }
  const double r21 = h[1] / h[0], r32 = h[2] / h[1];
  if (std::abs(e32) <= std::abs(e21)) {  // the differences do not shrink towards the fine end: p <= 0
    r.status = RichardsonStatus::OrderOutOfRange;
    r.order = std::log(e32 / e21) / std::log(r21);
    return r;
  }
  r.order = observed_order(r21, r32, e32 / e21);
  if (!std::isfinite(r.order) || r.order < kMinObservedOrder || r.order > kMaxObservedOrder) {
    r.status = RichardsonStatus::OrderOutOfRange;
    return r;
  }
  const double rp = std::pow(r21, r.order);
  r.status = RichardsonStatus::Extrapolated;
  r.extrapolated = (rp * f[0] - f[1]) / (rp - 1.0);
  r.fine_error = relative_error(f[0], r.extrapolated);
  r.fine_gci = kGciSafetyFactor * std::abs(e21 / f[0]) / (rp - 1.0);
  return r;
}

double relative_error(double f, double extrapolated) {
  return extrapolated != 0.0 ? (f - extrapolated) / extrapolated : 0.0;
}

double resolution_for_error(double h, double error, double order, double target) {
  return h * std::pow(target / std::abs(error), 1.0 / order);
}

}  // namespace vascsim
