#include "vascsim/run/region_builder.hpp"

#include <cmath>
#include <fmt/format.h>

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
    throw InputError(fmt::format("{}: region '{}': selector '{}' needs a vessel geometry (tube, vessel or mesh)",
                                 scene.file, reg.name, s.type));
  if (needs_line && !wall->has_centerline())
    throw InputError(fmt::format("{}: region '{}': selector '{}' needs a centre-line (tube or vessel geometry); "
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
      hit = s.end == "start" ? wall->s_m[i] <= s.depth_m + tol : wall->s_m[i] >= wall->length_m - s.depth_m - tol;
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
      throw InputError(fmt::format("{}: key 'regions.{}.select': region '{}' selects no nodes", scene.file,
                                   &rs - scene.regions.data(), rs.name));
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
