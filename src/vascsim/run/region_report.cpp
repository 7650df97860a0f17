#include "vascsim/run/region_report.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

#include "vascsim/geometry/boundary.hpp"
#include "vascsim/run/region_builder.hpp"

namespace vascsim {

namespace {

// Each surface node's share (one third of every boundary triangle around it) of the surface it lies on.
std::vector<double> surface_shares(const Discretization& disc, const WallCoordinates& wall, bool outer) {
  std::vector<char> on(disc.rest_positions().size(), 0);
  for (std::size_t i = 0; i < on.size(); ++i)
    on[i] = outer ? wall.on_outer(static_cast<Index>(i)) : wall.on_inner(static_cast<Index>(i));
  return lumped_boundary_area(disc.rest_positions(), boundary_faces(disc.tets()), on);
}

double selected_area(const std::vector<double>& shares, const std::vector<Index>& nodes) {
  double a = 0.0;
  for (Index i : nodes) a += shares[static_cast<std::size_t>(i)];
  return a;
}

// Area of the wall surface at distance r from the centre-line over |theta - c| <= w, s in [s0, s1]: the
// midpoint rule on 32 x 32 cells of |dX/ds x dX/dtheta| with X = C(s) + r radial(s, theta).
double swept_area(const WallCoordinates& wall, double r, double theta_c, double half_width, double s0,
                  double s1) {
  constexpr int n = 32;
  const double ds = (s1 - s0) / n, dth = 2.0 * half_width / n, h = 1e-6 * std::max(wall.length_m, r);
  const double rad = std::numbers::pi / 180.0;
  auto point = [&](double s, double th) {
    return Vec3(wall.centerline->position(s) + r * wall.radial(s, th));
  };
  double area = 0.0;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      const double s = std::clamp(s0 + (a + 0.5) * ds, h, wall.length_m - h),
                   th = theta_c - half_width + (b + 0.5) * dth;
      const Vec3 xs = (point(s + h, th) - point(s - h, th)) / (2.0 * h);
      const Vec3 xt = r * (wall.radial(s, th + 90.0)) * rad;  // d(radial)/d(theta) is the radial 90 deg on
      area += xs.cross(xt).norm() * ds * dth;
    }
  return area;
}

// A selected extent against the asked one; `scale` is what the difference is a fraction of (the asked width
// or area), `limit` the largest accepted fraction.
struct Mismatch {
  double asked, selected, scale, limit;
};

void warn_if(RegionSelection& out, const std::string& key, const Mismatch& m, const std::string& what,
             const std::string& unit, const std::string& hint) {
  const double fraction = (m.selected - m.asked) / m.scale;
  if (!(std::abs(fraction) > m.limit)) return;
  out.warnings.push_back(fmt::format(
      "region '{}' (key '{}'): selects {} {:.4g} {} where {:.4g} {} was asked ({:+.1f} % "
      "of the asked extent; the limit is {:.0f} %); {}",
      out.name, key, what, m.selected, unit, m.asked, unit, 100.0 * fraction, 100.0 * m.limit, hint));
}

// edges: the patch is measured by its nodes' span (geometry.fit_lattice_to_patch "edges"), else by their
// strips.
void describe_wall_patch(const SelectorSpec& s, const WallCoordinates& wall, const Discretization& disc,
                         const Region& region, bool edges, RegionSelection& out) {
  const double width = 2.0 * s.angle_half_width_deg, length = 2.0 * s.s_half_length_m;
  const double s_c = wall_patch_center_s(s, wall);
  double lo = 1e9, hi = -1e9, s_lo = 1e30, s_hi = -1e30, r = 0.0;
  std::size_t k_lo = 0, k_hi = 0, k_s_lo = 0, k_s_hi = 0;  // the outermost nodes
  std::set<long long> columns, cross_sections;             // on a graded lattice, counted by their positions
  for (Index i : region.nodes) {
    const auto k = static_cast<std::size_t>(i);
    const double d = std::remainder(wall.theta_deg[k] - s.angle_center_deg, 360.0);
    if (d < lo) lo = d, k_lo = k;
    if (d > hi) hi = d, k_hi = k;
    if (wall.s_m[k] < s_lo) s_lo = wall.s_m[k], k_s_lo = k;
    if (wall.s_m[k] > s_hi) s_hi = wall.s_m[k], k_s_hi = k;
    columns.insert(std::llround(d / (1e-6 * wall.angle_step_deg)));
    cross_sections.insert(std::llround(wall.s_m[k] / (1e-6 * wall.s_step_m)));
    r += (disc.rest_positions()[k] - wall.centerline->position(wall.s_m[k])).norm() / region.nodes.size();
  }
  // The strips the nodes stand for: half a lattice step beyond the outermost columns and cross-sections
  // (not beyond the vessel's ends; on a graded lattice the outermost nodes' own cells).
  // Measured by span instead, the outermost nodes themselves: the surface a prescribed displacement holds.
  const double step = wall.angle_step_deg;
  const bool graded = !wall.cells.empty();
  double a0 = lo, a1 = hi, z0 = s_lo, z1 = s_hi;
  if (!edges && graded) {
    a0 += wall.cells[k_lo].theta_lo_deg, a1 += wall.cells[k_hi].theta_hi_deg;
    z0 = wall.cells[k_s_lo].s_lo_m, z1 = wall.cells[k_s_hi].s_hi_m;
  } else if (!edges) {
    a0 -= 0.5 * step, a1 += 0.5 * step;
    z0 = std::max(0.0, s_lo - 0.5 * wall.s_step_m), z1 = std::min(wall.length_m, s_hi + 0.5 * wall.s_step_m);
  }
  const double asked_z0 = std::max(0.0, s_c - s.s_half_length_m),
               asked_z1 = std::min(wall.length_m, s_c + s.s_half_length_m);
  const double asked_area =
      swept_area(wall, r, s.angle_center_deg, s.angle_half_width_deg, asked_z0, asked_z1);
  const double area = edges
                          ? swept_area(wall, r, s.angle_center_deg + 0.5 * (lo + hi), 0.5 * (hi - lo), z0, z1)
                          : selected_area(surface_shares(disc, wall, s.surface == "outer"), region.nodes);
  out.report["asked"] = {{"angle_deg", width},
                         {"angle_center_deg", s.angle_center_deg},
                         {"length_m", asked_z1 - asked_z0},
                         {"s_center_m", s_c},
                         {"area_m2", asked_area}};
  out.report["selected"] = {
      {"angle_deg", a1 - a0},
      {"angle_center_deg", s.angle_center_deg + 0.5 * (lo + hi)},
      {"length_m", z1 - z0},
      {"s_center_m", 0.5 * (z0 + z1)},
      {"area_m2", area},
      {"columns", graded ? static_cast<long>(columns.size()) : std::lround((hi - lo) / step) + 1},
      {"cross_sections",
       graded ? static_cast<long>(cross_sections.size()) : std::lround((s_hi - s_lo) / wall.s_step_m) + 1},
      {"lattice_angle_step_deg", step},
      {"lattice_s_step_m", wall.s_step_m},
      {"measured_as", edges ? "edges" : "strips"}};
  const double f = kSelectionTolerance, f_area = (1.0 + f) * (1.0 + f) - 1.0;
  const std::string lattice = fmt::format(
      "the lattice steps are {:.4g} deg and {:.4g} m (geometry.node_spacing_m, "
      "geometry.lattice_angle_deg)",
      step, wall.s_step_m);
  const double asked_length = asked_z1 - asked_z0;
  warn_if(out, "angle_half_width_deg", {width, a1 - a0, width, f}, "an angle of", "deg", lattice);
  warn_if(out, "angle_center_deg", {0.0, 0.5 * (lo + hi), width, f}, "a centre offset by", "deg", lattice);
  if (length > 0.0) {
    warn_if(out, "s_half_length_m", {asked_length, z1 - z0, asked_length, f}, "a length of", "m", lattice);
    warn_if(out, "s_center_m", {0.0, 0.5 * (z0 + z1) - 0.5 * (asked_z0 + asked_z1), asked_length, f},
            "a centre offset by", "m", lattice);
    warn_if(out, "angle_half_width_deg", {asked_area, area, asked_area, f_area}, "an area of", "m^2",
            lattice);
  }
}

void describe_surface_patch(const SelectorSpec& s, const WallCoordinates& wall, const Discretization& disc,
                            const Region& region, RegionSelection& out) {
  const double asked = std::numbers::pi * s.radius_m * s.radius_m;
  const double area = selected_area(surface_shares(disc, wall, s.surface == "outer"), region.nodes);
  out.report["asked"] = {{"radius_m", s.radius_m}, {"area_m2", asked}};
  out.report["selected"] = {{"area_m2", area}, {"equivalent_radius_m", std::sqrt(area / std::numbers::pi)}};
  const double f = kSelectionTolerance;
  warn_if(
      out, "radius_m", {asked, area, asked, (1.0 + f) * (1.0 + f) - 1.0}, "an area of", "m^2",
      "the asked area is that of a flat disc; a radius of a few node spacings or more selects it closely");
}

nlohmann::json bounds(const Discretization& disc, const std::vector<Index>& nodes) {
  Eigen::AlignedBox3d box;
  for (Index i : nodes) box.extend(disc.rest_positions()[static_cast<std::size_t>(i)]);
  return {{"min_m", {box.min().x(), box.min().y(), box.min().z()}},
          {"max_m", {box.max().x(), box.max().y(), box.max().z()}}};
}

}  // namespace

std::vector<RegionSelection> describe_selections(const Scene& scene, const Discretization& disc,
                                                 const Body& body, const std::vector<Region>& regions) {
  std::vector<RegionSelection> out;
  for (std::size_t k = 0; k < regions.size(); ++k) {
    const SelectorSpec& s = scene.regions[k].select;
    RegionSelection r;
    r.name = regions[k].name;
    r.report = {{"name", r.name},
                {"selector", s.type},
                {"nodes", regions[k].nodes.size()},
                {"selected_bounds", bounds(disc, regions[k].nodes)}};
    if (s.type == "wall_patch" && body.wall && body.wall->angle_step_deg > 0.0)
      describe_wall_patch(s, *body.wall, disc, regions[k],
                          scene.geometry.fit_lattice_to_patch == "edges" || scene.geometry.refine.enabled, r);
    else if (s.type == "surface_patch" && body.wall)
      describe_surface_patch(s, *body.wall, disc, regions[k], r);
    else if (s.type == "cylinder_end")
      r.report["asked"] = {{"end", s.end}, {"depth_m", s.depth_m}};
    else if (s.type == "box")
      r.report["asked"] = {{"min_m", {s.min_m.x(), s.min_m.y(), s.min_m.z()}},
                           {"max_m", {s.max_m.x(), s.max_m.y(), s.max_m.z()}}};
    r.report["warnings"] = r.warnings;
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace vascsim
