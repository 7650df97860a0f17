#include "vascsim/geometry/lattice_fit.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace vascsim {

namespace {

// Columns selected by a patch of half width w (deg) whose centre sits on a column (odd count) or half way
// between two (even count), with `step` deg between columns: the selector keeps |dtheta| <= w.
int columns_selected(double w, double step, bool centred_on_column) {
  const double tol = 1e-9;
  return centred_on_column ? 2 * static_cast<int>(std::floor(w / step + tol)) + 1
                           : 2 * static_cast<int>(std::floor(w / step + 0.5 + tol));
}

// The extent a patch selects, as PatchFit says, over its asked extent, minus 1: n selected lines `step` apart
// cover n steps as strips and span n - 1 steps edge to edge. A patch of zero width (one line) is met exactly
// only by a single line edge to edge; otherwise the error is one step, the same for every count.
double extent_error(int selected, double step, double asked, PatchFit mode) {
  const int steps = mode == PatchFit::Strips ? selected : selected - 1;
  if (!(asked > 0.0)) return selected == 1 && mode == PatchFit::Edges ? 0.0 : 1.0;
  return steps * step / asked - 1.0;
}

// The cross-sections at s_k = k L / (nz - 1) within half_length of the centre: as strips (clipped at the
// vessel's ends), their count times the step against the asked length; edge to edge, the larger of the two
// edges' misses.
double cross_section_error(double centre, double half_length, double length, int nz, PatchFit mode) {
  const double step = length / (nz - 1), tol = 1e-6 * step;
  int n = 0;
  double lo = 1e300, hi = -1e300;
  for (int k = 0; k < nz; ++k)
    if (std::abs(k * step - centre) <= half_length + tol) {
      ++n;
      lo = std::min(lo, k * step), hi = std::max(hi, k * step);
    }
  if (mode == PatchFit::Strips || !(half_length > 0.0)) return extent_error(n, step, 2.0 * half_length, mode);
  if (n < 2) return -1.0;
  const double miss = std::max(std::abs(lo - std::max(0.0, centre - half_length)),
                               std::abs(hi - std::min(length, centre + half_length)));
  return (hi - lo < 2.0 * half_length ? -1.0 : 1.0) * miss / (2.0 * half_length);
}

}  // namespace

LatticeFit fit_lattice_to_patch(const TubeSpec& tube, const PatchExtent& patch, double length_m,
                                PatchFit mode) {
  LatticeFit fit;
  const double r_mid = tube.outer_radius_m - 0.5 * tube.wall_thickness_m;
  const int nt0 = lattice_columns(r_mid, tube.node_spacing_m);
  const int nz0 = lattice_cross_sections(length_m, tube.node_spacing_m);
  const double width = 2.0 * patch.angle_half_width_deg;
  double best = 1e300;
  for (int nt = std::max(8, static_cast<int>(std::ceil(0.75 * nt0))); nt <= static_cast<int>(1.5 * nt0);
       ++nt) {
    const double step = 360.0 / nt;
    for (bool on_column : {true, false}) {
      const double err =
          extent_error(columns_selected(patch.angle_half_width_deg, step, on_column), step, width, mode);
      const double score = std::abs(err) + 1e-6 * std::abs(nt - nt0);
      if (score < best) {
        best = score;
        fit.angular_nodes = nt;
        fit.angle_error = err;
        fit.lattice_angle_deg = patch.angle_center_deg + (on_column ? 0.0 : 0.5 * step);
      }
    }
  }
  const double centre = patch.s_center_m;
  best = 1e300;
  for (int nz = std::max(2, static_cast<int>(std::ceil(0.75 * nz0))); nz <= static_cast<int>(1.5 * nz0);
       ++nz) {
    const double err = cross_section_error(centre, patch.s_half_length_m, length_m, nz, mode);
    const double score = std::abs(err) + 1e-6 * std::abs(nz - nz0);
    if (score < best) {
      best = score;
      fit.axial_nodes = nz;
      fit.length_error = err;
    }
  }
  fit.summary = fmt::format(
      "lattice fitted to the first wall patch's {}: {} columns ({} from the spacing) and {} cross-sections "
      "({}); the "
      "patch selects {:+.1f} % of its angle and {:+.1f} % of its length",
      mode == PatchFit::Strips ? "strips" : "edges", fit.angular_nodes, nt0, fit.axial_nodes, nz0,
      100.0 * fit.angle_error, 100.0 * fit.length_error);
  return fit;
}

}  // namespace vascsim
