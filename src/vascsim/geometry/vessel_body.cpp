#include "vascsim/geometry/vessel_body.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "vascsim/geometry/boundary.hpp"
#include "vascsim/geometry/mesh_wall.hpp"
#include "vascsim/geometry/swept_vessel.hpp"
#include "vascsim/geometry/vertex_normals.hpp"

namespace vascsim {

namespace {

// A triangle is on the outer wall when its three vertices are.
template <class IsOuterVertex>
std::vector<char> outer_triangles(const std::vector<std::array<Index, 3>>& triangles,
                                  IsOuterVertex&& is_outer) {
  std::vector<char> out;
  out.reserve(triangles.size());
  for (const auto& t : triangles) out.push_back(is_outer(t[0]) && is_outer(t[1]) && is_outer(t[2]) ? 1 : 0);
  return out;
}

// Column k's angle, rad, continued past the seam (k = -1 is the last column one turn back, k = nt the first
// one turn on).
double column_angle(const SweptVessel& v, int k) {
  const int nt = v.angular_nodes;
  const int wrapped = ((k % nt) + nt) % nt;
  return v.theta_rad[static_cast<std::size_t>(wrapped)] + 2.0 * std::numbers::pi * ((k - wrapped) / nt);
}

}  // namespace

Vec3 WallCoordinates::radial(double s, double theta) const {
  const Frame f = centerline->frame(s);
  const double th = theta * std::numbers::pi / 180.0;
  return std::cos(th) * f.N + std::sin(th) * f.B;
}

Body body_from_swept_vessel(SweptVessel v, std::shared_ptr<const Centerline> centerline) {
  const int nr = v.radial_layers, nt = v.angular_nodes, nz = v.axial_nodes;
  const std::size_t n = v.cloud.positions.size();
  WallCoordinates w;
  w.centerline = std::move(centerline);
  w.length_m = v.length_m;
  w.depth_m.resize(n);
  w.s_m.resize(n);
  w.theta_deg.resize(n);
  w.outward.resize(n);
  // Thickness from the geometry itself: the distance between the inner and outer layer of node 0's ray.
  w.thickness_m = (v.cloud.positions[static_cast<std::size_t>(nr - 1)] - v.cloud.positions[0]).norm();
  w.shell_tolerance_m = 0.01 * w.thickness_m / (nr - 1);
  w.layer_spacing_m = w.thickness_m / (nr - 1);
  w.angle_step_deg = 360.0 / nt;
  w.s_step_m = v.length_m / (nz - 1);
  if (v.graded) {
    // The nominal steps are the finest ones; each node's own cell is in w.cells.
    w.angle_step_deg = 360.0, w.s_step_m = v.length_m;
    for (int it = 0; it < nt; ++it) {
      const double step_rad = column_angle(v, it + 1) - column_angle(v, it);
      w.angle_step_deg = std::min(w.angle_step_deg, step_rad * 180.0 / std::numbers::pi);
    }
    for (int iz = 0; iz + 1 < nz; ++iz) w.s_step_m = std::min(w.s_step_m, v.s_m[iz + 1] - v.s_m[iz]);
    w.cells.resize(n);
  }
  for (int iz = 0; iz < nz; ++iz) {
    const double s = v.s_m[static_cast<std::size_t>(iz)];
    const Frame f = w.centerline->frame(s);
    for (int it = 0; it < nt; ++it) {
      const double th = v.theta_rad[static_cast<std::size_t>(it)];
      const Vec3 dir = std::cos(th) * f.N + std::sin(th) * f.B;
      LatticeCell cell;
      if (v.graded) {
        // Half-way to the neighbouring columns and cross-sections (the vessel's ends close the cell there).
        cell.theta_lo_deg = -0.5 * (th - column_angle(v, it - 1)) * 180.0 / std::numbers::pi;
        cell.theta_hi_deg = 0.5 * (column_angle(v, it + 1) - th) * 180.0 / std::numbers::pi;
        cell.s_lo_m = iz > 0 ? 0.5 * (v.s_m[iz - 1] + s) : s;
        cell.s_hi_m = iz + 1 < nz ? 0.5 * (v.s_m[iz + 1] + s) : s;
      }
      for (int ir = 0; ir < nr; ++ir) {
        const auto i = static_cast<std::size_t>(ir + nr * (it + nt * iz));
        w.depth_m[i] = w.thickness_m * ir / (nr - 1);
        w.s_m[i] = s;
        w.theta_deg[i] = v.theta_deg[static_cast<std::size_t>(it)];
        w.outward[i] = dir;
        if (v.graded) w.cells[i] = cell;
      }
    }
  }
  RenderSurface surf;
  const std::size_t nsurf = static_cast<std::size_t>(nt) * nz;
  surf.rest_vertices.resize(2 * nsurf);
  // The surface vertices are the outer (ir = nr-1) and inner (ir = 0) node layers; take them from the
  // cloud so a caller that substitutes an equivalent cloud (make_tube) stays bit-consistent.
  for (std::size_t k = 0; k < nsurf; ++k) {
    surf.rest_vertices[k] =
        v.cloud.positions[static_cast<std::size_t>(nr) * k + static_cast<std::size_t>(nr - 1)];
    surf.rest_vertices[nsurf + k] = v.cloud.positions[static_cast<std::size_t>(nr) * k];
  }
  surf.rest_normals = std::move(v.normals);
  surf.uv = std::move(v.uv);
  surf.triangles = std::move(v.triangles);
  surf.outer = outer_triangles(surf.triangles, [&](Index v) { return static_cast<std::size_t>(v) < nsurf; });
  Body b;
  b.cloud = std::move(v.cloud);
  b.wall = std::move(w);
  b.surface = std::move(surf);
  return b;
}

Body body_from_tube(NodeCloud tube, SweptVessel swept) {
  const TubeShape& shape = tube.tube.value();
  auto cl = std::make_shared<const Centerline>(straight_centerline(shape.length_m));
  Body b = body_from_swept_vessel(std::move(swept), cl);
  WallCoordinates& w = *b.wall;
  const std::size_t n = tube.positions.size();
  w.thickness_m = shape.outer_radius_m - shape.inner_radius_m;
  w.shell_tolerance_m = 0.01 * w.thickness_m / (shape.radial_layers - 1);
  w.layer_spacing_m = w.thickness_m / (shape.radial_layers - 1);
  w.depth_m.resize(n);
  w.s_m.resize(n);
  w.theta_deg.resize(n);
  w.outward.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p = tube.positions[i];
    w.depth_m[i] = std::hypot(p.x(), p.y()) - shape.inner_radius_m;
    w.s_m[i] = p.z();
    const double th = std::atan2(p.y(), p.x()) * 180.0 / std::numbers::pi;
    w.theta_deg[i] = th < 0.0 ? th + 360.0 : th;
    w.outward[i] = Vec3(p.x(), p.y(), 0.0).normalized();
  }
  b.cloud = std::move(tube);
  return b;
}

Body body_from_mesh_wall(MeshWall m) {
  WallCoordinates w;
  w.thickness_m = m.thickness_m;
  w.depth_m = std::move(m.depth_m);
  w.outward = std::move(m.outward);
  w.surface_tag = std::move(m.node_surface);
  RenderSurface surf;
  surf.rest_vertices = std::move(m.surface_vertices);
  surf.rest_normals = std::move(m.normals);
  surf.triangles = std::move(m.triangles);
  surf.outer = outer_triangles(surf.triangles,
                               [&](Index v) { return m.surface_is_outer[static_cast<std::size_t>(v)] != 0; });
  Body b;
  b.cloud = std::move(m.cloud);
  b.wall = std::move(w);
  b.surface = std::move(surf);
  return b;
}

Body body_from_lattice(NodeCloud cloud) {
  RenderSurface surf;
  const auto faces = boundary_faces(cloud.tets);
  // Compact the boundary nodes into surface vertices.
  std::vector<Index> vertex_of(cloud.positions.size(), -1);
  for (const Triangle& f : faces) {
    std::array<Index, 3> t{};
    for (int c = 0; c < 3; ++c) {
      Index& v = vertex_of[static_cast<std::size_t>(f[c])];
      if (v < 0) {
        v = static_cast<Index>(surf.rest_vertices.size());
        surf.rest_vertices.push_back(cloud.positions[static_cast<std::size_t>(f[c])]);
      }
      t[c] = v;
    }
    surf.triangles.push_back(t);
  }
  surf.outer.assign(surf.triangles.size(), 1);
  vertex_normals(surf.triangles, surf.rest_vertices, surf.rest_normals);
  Body b;
  b.cloud = std::move(cloud);
  b.surface = std::move(surf);
  return b;
}

double mean_node_radius_m(const Body& body) {
  const WallCoordinates& wall = *body.wall;
  const Vec3Array& X = body.cloud.positions;
  double radius = 0.0;
  for (std::size_t i = 0; i < X.size(); ++i) radius += (X[i] - wall.centerline->position(wall.s_m[i])).norm();
  return radius / static_cast<double>(X.size());
}

double along_wall_spacing_m(const Body& body) {
  if (!body.wall) return body.cloud.spacing_m;
  const WallCoordinates& wall = *body.wall;
  if (!wall.has_centerline() || !(wall.angle_step_deg > 0.0) || !(wall.s_step_m > 0.0) ||
      body.cloud.positions.empty())
    return body.cloud.spacing_m;
  return std::sqrt(mean_node_radius_m(body) * wall.angle_step_deg * std::numbers::pi / 180.0 * wall.s_step_m);
}

}  // namespace vascsim
