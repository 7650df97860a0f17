#include "vascsim/run/region_builder.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>

#include "vascsim/core/error.hpp"
#include "vascsim/geometry/boundary.hpp"

namespace vascsim {

double wall_patch_center_s(const SelectorSpec& s, const WallCoordinates& wall) {
  return s.s_center_fraction >= 0.0 ? s.s_center_fraction * wall.length_m : s.s_center_m;
}

namespace {

std::vector<char> select_nodes(const SelectorSpec& s, const RegionSpec& reg, const Scene& scene,
                               const Discretization& disc, const Body& body) {
  const Vec3Array& X = disc.rest_positions();
  const auto& wall = body.wall;
  const double tol = 1e-6 * disc.mean_spacing();
  std::vector<char> in(X.size(), 0);
  const bool needs_wall = s.type == "cylinder_end" || s.type == "wall_patch" || s.type == "surface_patch";
  const bool needs_line = s.type == "cylinder_end" || s.type == "wall_patch";
  if (needs_wall && !wall)
    throw InputError(
        fmt::format("{}: region '{}': selector '{}' needs a vessel geometry (tube, vessel or mesh)",
                    scene.file, reg.name, s.type));
  if (needs_line && !wall->has_centerline())
    throw InputError(
        fmt::format("{}: region '{}': selector '{}' needs a centre-line (tube or vessel geometry); "
                    "use surface_patch or box on an imported mesh",
                    scene.file, reg.name, s.type));
  for (std::size_t i = 0; i < X.size(); ++i) {
    const Vec3& p = X[i];
    const Index n = static_cast<Index>(i);
    bool hit = false;
    if (s.type == "all") {
      hit = true;
    } else if (s.type == "box") {
      hit = (p.array() >= s.min_m.array() - tol).all() && (p.array() <= s.max_m.array() + tol).all();
    } else if (s.type == "cylinder_end") {
      hit = s.end == "start" ? wall->s_m[i] <= s.depth_m + tol
                             : wall->s_m[i] >= wall->length_m - s.depth_m - tol;
    } else {
      const bool on_surface = s.surface == "outer" ? wall->on_outer(n) : wall->on_inner(n);
      if (s.type == "wall_patch") {
        const double s_center = wall_patch_center_s(s, *wall);
        const double dtheta = std::remainder(wall->theta_deg[i] - s.angle_center_deg, 360.0);
        hit = on_surface && std::abs(dtheta) <= s.angle_half_width_deg + 1e-9 &&
              std::abs(wall->s_m[i] - s_center) <= s.s_half_length_m + tol;
      } else {  // surface_patch
        hit = on_surface && (p - s.centre_m).norm() <= s.radius_m + tol;
      }
    }
    in[i] = hit ? 1 : 0;
  }
  return in;
}

// "[x, y, z]", a bound a box selector leaves open as -inf or inf.
std::string point_text(const Vec3& p) {
  auto c = [](double x) {
    return std::abs(x) >= 1e29 ? std::string(x < 0.0 ? "-inf" : "inf") : fmt::format("{:.4g}", x);
  };
  return fmt::format("[{}, {}, {}]", c(p.x()), c(p.y()), c(p.z()));
}

// The advice when a selector's window misses the body's extent as typed and meets it divided by 1000, i.e.
// read in millimetres (the wording of tool_reach's message for a tool placed in millimetres). `meets(scale)`:
// whether the window, its lengths times scale, meets the body's extent.
template <class Meets>
std::string millimetres(const Meets& meets) {
  return !meets(1.0) && meets(1e-3)
             ? "; these values look like millimetres (divided by 1000 they meet the body): "
               "lengths are in metres"
             : "";
}

// Why a selector selected nothing: the body's extent in the selector's own coordinates beside the window
// asked.
std::string empty_selection_detail(const SelectorSpec& s, const Discretization& disc, const Body& body) {
  const Vec3Array& X = disc.rest_positions();
  const double tol = 1e-6 * disc.mean_spacing();
  if (s.type == "box") {
    Eigen::AlignedBox3d box;
    for (const Vec3& p : X) box.extend(p);
    const auto meets = [&](double scale) {
      return ((scale * s.min_m).array() <= box.max().array() + tol).all() &&
             ((scale * s.max_m).array() >= box.min().array() - tol).all();
    };
    return fmt::format(
        ": its box {} .. {} m (min_m, max_m) holds none of the body, whose nodes lie within {} .. {} "
        "m{}",
        point_text(s.min_m), point_text(s.max_m), point_text(box.min()), point_text(box.max()),
        millimetres(meets));
  }
  if (!body.wall) return "";
  const WallCoordinates& wall = *body.wall;
  if (s.type == "cylinder_end")
    return fmt::format(": depth_m {:.4g} m from its {}; the centre-line is {:.4g} m long", s.depth_m, s.end,
                       wall.length_m);
  // The nodes of the surface asked for.
  std::vector<Index> on;
  for (std::size_t i = 0; i < X.size(); ++i) {
    const Index n = static_cast<Index>(i);
    if (s.surface == "outer" ? wall.on_outer(n) : wall.on_inner(n)) on.push_back(n);
  }
  if (on.empty()) return fmt::format(": the body has no {} surface nodes", s.surface);
  if (s.type == "surface_patch") {
    Eigen::AlignedBox3d box;
    for (Index i : on) box.extend(X[static_cast<std::size_t>(i)]);
    const auto meets = [&](double scale) {
      return box.exteriorDistance(Vec3(scale * s.centre_m)) <= scale * s.radius_m + tol;
    };
    return fmt::format(
        ": its sphere of radius {:.4g} m (radius_m) round {} m (centre_m) holds none of the body's "
        "{} surface nodes, which lie within {} .. {} m{}",
        s.radius_m, point_text(s.centre_m), s.surface, point_text(box.min()), point_text(box.max()),
        millimetres(meets));
  }
  if (s.type != "wall_patch") return "";
  const double s_c = wall_patch_center_s(s, wall);
  double s_lo = 1e300, s_hi = -1e300, nearest_angle = 360.0, nearest_s = 1e300;
  for (Index i : on) {
    const auto k = static_cast<std::size_t>(i);
    s_lo = std::min(s_lo, wall.s_m[k]);
    s_hi = std::max(s_hi, wall.s_m[k]);
    nearest_angle =
        std::min(nearest_angle, std::abs(std::remainder(wall.theta_deg[k] - s.angle_center_deg, 360.0)));
    nearest_s = std::min(nearest_s, std::abs(wall.s_m[k] - s_c));
  }
  // Only a centre given in metres can have been typed in millimetres (s_center_fraction is a fraction).
  const auto meets = [&](double scale) {
    return s.s_center_fraction >= 0.0 || (scale * (s_c - s.s_half_length_m) <= s_hi + tol &&
                                          scale * (s_c + s.s_half_length_m) >= s_lo - tol);
  };
  return fmt::format(
      ": its window is {:.4g} +- {:.4g} deg round the centre-line (angle_center_deg, "
      "angle_half_width_deg) and s = {:.4g} +- {:.4g} m along it (s_center_m, s_half_length_m); the "
      "body's {} surface nodes lie at s = {:.4g} .. {:.4g} m, their cross-section nearest s = {:.4g} m "
      "is {:.4g} m from it (a cross-section every {:.4g} m) and their column nearest {:.4g} deg is "
      "{:.4g} deg from it (a column every {:.4g} deg){}",
      s.angle_center_deg, s.angle_half_width_deg, s_c, s.s_half_length_m, s.surface, s_lo, s_hi, s_c,
      nearest_s, wall.s_step_m, s.angle_center_deg, nearest_angle, wall.angle_step_deg, millimetres(meets));
}

// The "inward" direction of a patch: into the wall at the patch centre (wall_patch: minus the radial
// direction of the centre-line frame; surface_patch: minus the mean outward normal of its nodes).
Vec3 inward_direction(const SelectorSpec& s, const WallCoordinates& wall, const std::vector<Index>& nodes) {
  if (s.type == "wall_patch") return -wall.radial(wall_patch_center_s(s, wall), s.angle_center_deg);
  Vec3 sum = Vec3::Zero();
  for (Index i : nodes) sum += wall.outward[static_cast<std::size_t>(i)];
  return -sum.normalized();
}

}  // namespace

std::vector<Region> build_regions(const Scene& scene, const Discretization& disc, const Body& body) {
  std::vector<Region> out;
  const auto faces = boundary_faces(disc.tets());
  for (const RegionSpec& rs : scene.regions) {
    Region r;
    r.name = rs.name;
    r.bc = rs.bc;
    const std::vector<char> in = select_nodes(rs.select, rs, scene, disc, body);
    for (std::size_t i = 0; i < in.size(); ++i)
      if (in[i]) r.nodes.push_back(static_cast<Index>(i));
    if (r.nodes.empty())
      throw InputError(fmt::format("{}: key 'regions.{}.select': region '{}' selects no nodes{}", scene.file,
                                   &rs - scene.regions.data(), rs.name,
                                   empty_selection_detail(rs.select, disc, body)));
    const Vec3 dir = rs.direction_inward ? inward_direction(rs.select, *body.wall, r.nodes) : rs.direction;
    r.direction = dir;
    r.release_time_s = rs.release_time_s;
    const Vec3 vec = rs.has_vector ? rs.vector : Vec3(rs.magnitude * dir);
    if (r.bc == RegionBcType::Displacement) r.displacement_m = vec;
    if (r.bc == RegionBcType::Force) {
      r.force_n = vec;
      // Spread by the boundary area lying inside the region; regions without such area by volume.
      const auto area = lumped_boundary_area(disc.rest_positions(), faces, in);
      double total = 0.0;
      for (Index i : r.nodes) total += area[i];
      for (Index i : r.nodes) r.force_weights.push_back(total > 0.0 ? area[i] / total : disc.volumes()[i]);
      if (!(total > 0.0)) {
        double vt = 0.0;
        for (double w : r.force_weights) vt += w;
        for (double& w : r.force_weights) w /= vt;
      }
    }
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace vascsim
