#include "vascsim/run/body_builder.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "vascsim/core/error.hpp"
#include "vascsim/geometry/mesh_wall.hpp"
#include "vascsim/geometry/swept_vessel.hpp"
#include "vascsim/io/mesh_import.hpp"

namespace vascsim {

namespace {

Body body_from_mesh(const MeshGeometrySpec& spec) {
  const TriangleMesh mesh = import_triangle_mesh(spec.file, spec.units_m);
  MeshWallSpec ws;
  ws.kind = spec.kind;
  ws.wall_thickness_m = spec.wall_thickness_m;
  ws.node_spacing_m = spec.node_spacing_m;
  ws.min_layers = spec.min_layers;
  ws.source = spec.file;
  return body_from_mesh_wall(make_mesh_wall(mesh, ws));
}

// geometry.refine.around: the window's centre is the centre-line's point nearest the tool and the tool's
// angle around it there.
void centre_window_on(const std::string& tool, const Vec3& point_m, const Centerline& line,
                      WallRefinement& w) {
  const double s = line.closest_arc_length(point_m);
  const Frame f = line.frame(s);
  const Vec3 radial = point_m - line.position(s);
  const Vec3 in_plane = radial - radial.dot(f.T) * f.T;
  if (in_plane.norm() < 1e-9 * std::max(1.0, line.length()))
    throw InputError(
        fmt::format("geometry.refine.around: the obstacle '{}' stands on the centre-line, so it has no "
                    "angle around it; give angle_center_deg and s_center_m instead",
                    tool));
  double theta = std::atan2(in_plane.dot(f.B), in_plane.dot(f.N)) * 180.0 / std::numbers::pi;
  if (theta < 0.0) theta += 360.0;
  w.angle_center_deg = theta;
  w.s_center_m = s;
}

}  // namespace

Body build_body(const GeometrySpec& spec) {
  if (spec.type == "tube") {
    SweptVesselSpec ss{spec.tube.outer_radius_m,    spec.tube.wall_thickness_m,
                       spec.tube.node_spacing_m,    std::max(3, spec.tube.min_layers),
                       spec.tube.lattice_angle_deg, spec.tube.angular_nodes,
                       spec.tube.axial_nodes,       {}};
    return body_from_tube(make_tube(spec.tube),
                          make_swept_vessel(straight_centerline(spec.tube.length_m), ss));
  }
  if (spec.type == "vessel") {
    const CenterlineSpec& c = spec.centerline;
    auto line = std::make_shared<const Centerline>(build_centerline(c));
    SweptVesselSpec ss{spec.tube.outer_radius_m,    spec.tube.wall_thickness_m,
                       spec.tube.node_spacing_m,    spec.tube.min_layers,
                       spec.tube.lattice_angle_deg, spec.tube.angular_nodes,
                       spec.tube.axial_nodes,       spec.refine};
    if (ss.refine.enabled && spec.refine_s_center_fraction >= 0.0)
      ss.refine.s_center_m = spec.refine_s_center_fraction * line->length();
    if (ss.refine.enabled && !spec.refine_around.empty())
      centre_window_on(spec.refine_around, spec.refine_around_point_m, *line, ss.refine);
    return body_from_swept_vessel(make_swept_vessel(*line, ss), line);
  }
  if (spec.type == "mesh") return body_from_mesh(spec.mesh);
  NodeCloud c = make_box(spec.box);
  if (spec.type == "beam") c.kind = "beam";
  return body_from_lattice(std::move(c));
}

NodeCloud build_geometry(const GeometrySpec& spec) {
  return build_body(spec).cloud;
}

std::vector<materials::MaterialFrame> wall_frames(const Body& body, const Scene& scene) {
  if (!body.wall || !body.wall->has_centerline())
    throw InputError(
        fmt::format("{}: key 'material.law': '{}' takes its fibre directions from the vessel's "
                    "centre-line; geometry '{}' has none (use a tube or a vessel)",
                    scene.file, scene.material_law, scene.geometry.type));
  const WallCoordinates& w = *body.wall;
  std::vector<materials::MaterialFrame> frames(body.cloud.positions.size());
  for (std::size_t i = 0; i < frames.size(); ++i)
    frames[i] = materials::make_material_frame(w.centerline->tangent(w.s_m[i]), w.outward[i]);
  return frames;
}

}  // namespace vascsim
