#include "vascsim/geometry/graded_axis.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "vascsim/core/error.hpp"

namespace vascsim {

namespace {

void check(const AxisGrading& g) {
  if (!(std::isfinite(g.fine_m) && g.fine_m > 0.0))
    throw InputError("graded lattice: the fine spacing must be > 0");
  if (!(std::isfinite(g.coarse_m) && g.coarse_m >= g.fine_m))
    throw InputError(
        fmt::format("graded lattice: the coarse spacing ({:.4g} m) must be at least the fine one ({:.4g} m)",
                    g.coarse_m, g.fine_m));
  if (!(std::isfinite(g.growth) && g.growth > 1.0 && g.growth <= 3.0))
    throw InputError(fmt::format("graded lattice: growth {} must lie in (1, 3]", g.growth));
}

// Equal steps of about `fine` over a span of length d (at least one).
int equal_steps(double d, double fine) {
  return std::max(1, static_cast<int>(std::lround(d / fine)));
}

// Steps that grow by `growth` from `fine` up to `coarse` (one side) or from both ends towards the middle
// (two_sided), scaled by one factor to sum to d; the count whose factor is nearest 1 wins. Empty for d <= 0.
std::vector<double> grown_steps(double d, const AxisGrading& g, bool two_sided) {
  if (!(d > 1e-12 * g.fine_m)) return {};
  // The k-th step from a grown edge (k = 0 next to the window).
  auto step = [&](int k) { return std::min(g.fine_m * std::pow(g.growth, k + 1), g.coarse_m); };
  std::vector<double> best;
  double best_misfit = 1e300;
  for (int n = 1;; ++n) {
    std::vector<double> s(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k)
      s[static_cast<std::size_t>(k)] = two_sided ? step(std::min(k, n - 1 - k)) : step(k);
    double sum = 0.0;
    for (double v : s) sum += v;
    const double misfit = std::abs(std::log(d / sum));
    if (misfit < best_misfit) {
      best_misfit = misfit;
      for (double& v : s) v *= d / sum;
      best = std::move(s);
    }
    if (sum > d) break;  // more steps only shrink them further
  }
  return best;
}

// The window's nodes: every break, and equal steps of about the fine spacing between two successive breaks.
void fill_window(const std::vector<double>& breaks, const AxisGrading& g, std::vector<double>& x) {
  for (std::size_t b = 0; b + 1 < breaks.size(); ++b) {
    const double a = breaks[b], c = breaks[b + 1];
    const int n = equal_steps(c - a, g.fine_m);
    for (int k = 1; k <= n; ++k) x.push_back(k == n ? c : a + (c - a) * k / n);
  }
}

void check_breaks(const std::vector<double>& breaks) {
  if (breaks.size() < 2) throw InputError("graded lattice: the refined window needs two edges");
  for (std::size_t b = 0; b + 1 < breaks.size(); ++b)
    if (!(std::isfinite(breaks[b]) && breaks[b + 1] > breaks[b]))
      throw InputError("graded lattice: the refined window's edges must increase");
}
}  // namespace

std::vector<double> graded_line(double length, std::vector<double> breaks, const AxisGrading& g) {
  check(g);
  if (!(std::isfinite(length) && length > 0.0))
    throw InputError("graded lattice: the axis's length must be > 0");
  for (double& b : breaks) b = std::clamp(b, 0.0, length);
  breaks.erase(std::unique(breaks.begin(), breaks.end()),
               breaks.end());  // a margin of 0, or a window at an end
  check_breaks(breaks);
  const double w0 = breaks.front(), w1 = breaks.back();
  const std::vector<double> before = grown_steps(w0, g, false);  // before[0] is next to the window
  std::vector<double> x{0.0};
  double p = 0.0;
  for (auto it = before.rbegin(); it != before.rend(); ++it) x.push_back(p += *it);
  x.back() = w0;
  fill_window(breaks, g, x);
  p = w1;
  const std::vector<double> after = grown_steps(length - w1, g, false);
  for (double s : after) x.push_back(p += s);
  x.back() = length;
  return x;
}

std::vector<double> graded_circle(double period, std::vector<double> breaks, const AxisGrading& g) {
  check(g);
  if (!(std::isfinite(period) && period > 0.0)) throw InputError("graded lattice: the period must be > 0");
  breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());  // a margin of 0
  check_breaks(breaks);
  const double w0 = breaks.front(), w1 = breaks.back();
  if (!(w1 - w0 < period))
    throw InputError("graded lattice: the refined window must be shorter than the period");
  std::vector<double> x{w0};
  fill_window(breaks, g, x);
  const std::vector<double> rest = grown_steps(period - (w1 - w0), g, true);
  double p = w1;
  for (std::size_t k = 0; k + 1 < rest.size(); ++k)
    x.push_back(p += rest[k]);  // the last step closes onto w0
  return x;
}

}  // namespace vascsim
