#include "vascsim/run/contact_surface_builder.hpp"

#include <fmt/format.h>
#include <algorithm>

#include "vascsim/core/error.hpp"
#include "vascsim/core/spatial_grid.hpp"
#include "vascsim/geometry/surface_samples.hpp"
#include "vascsim/mapping/mls_map.hpp"
#include "vascsim/mapping/surface_quadratic_fit.hpp"

namespace vascsim {

namespace {

double mean_edge(const RenderSurface& surf) {
  double sum = 0.0;
  for (const auto& t : surf.triangles)
    for (int k = 0; k < 3; ++k) sum += (surf.rest_vertices[t[(k + 1) % 3]] - surf.rest_vertices[t[k]]).norm();
  return sum / (3.0 * static_cast<double>(std::max<std::size_t>(surf.triangles.size(), 1)));
}

// The node at each vertex's position (within 1e-9 of the mean spacing), or -1.
std::vector<Index> node_at_vertex(const RenderSurface& surf, const Discretization& disc) {
  const double tol = 1e-9 * disc.mean_spacing();
  const SpatialGrid grid(disc.rest_positions(), disc.mean_spacing());
  std::vector<Index> node(surf.rest_vertices.size(), -1);
  for (std::size_t v = 0; v < surf.rest_vertices.size(); ++v)
    grid.for_each_within(surf.rest_vertices[v], tol, [&](Index i, double) { node[v] = i; });
  return node;
}

// Adds a correction to the row that starts at `first` of col/val: onto an entry of the same node, or
// appended.
void add_to_row(const SurfaceFitRow& add, std::size_t first, std::vector<Index>& col,
                std::vector<double>& val) {
  for (std::size_t k = 0; k < add.node.size(); ++k) {
    const auto end = col.end();
    const auto it = std::find(col.begin() + static_cast<std::ptrdiff_t>(first), end, add.node[k]);
    if (it != end) {
      val[static_cast<std::size_t>(it - col.begin())] += add.phi[k];
    } else {
      col.push_back(add.node[k]);
      val.push_back(add.phi[k]);
    }
  }
}

// The curvature corrections for the samples flagged in `want` (the others stay empty): fitted over the
// surface's nodes (each node once, with its vertex's normal), each sample at its interpolated normal on its
// triangle.
std::vector<SurfaceFitRow> curvature_rows(const RenderSurface& surf, const SurfaceSamples& samples,
                                          const std::vector<Index>& node, const std::vector<char>& want) {
  SurfaceNodes nodes;
  std::vector<char> seen;
  for (std::size_t v = 0; v < node.size(); ++v) {
    const Index i = node[v];
    if (i < 0) continue;
    if (static_cast<std::size_t>(i) >= seen.size()) seen.resize(static_cast<std::size_t>(i) + 1, 0);
    if (seen[static_cast<std::size_t>(i)]) continue;
    seen[static_cast<std::size_t>(i)] = 1;
    nodes.node.push_back(i);
    nodes.position_m.push_back(surf.rest_vertices[v]);
    nodes.normal.push_back(surf.rest_normals[v]);
  }
  Vec3Array points, normals;
  std::vector<SurfaceCorners> corners;
  std::vector<std::size_t> of;
  for (std::size_t v = 0; v < want.size(); ++v) {
    if (!want[v]) continue;
    const auto& t = surf.triangles[static_cast<std::size_t>(samples.triangle[v])];
    points.push_back(samples.positions[v]);
    normals.push_back(samples.normals[v]);
    corners.push_back({{surf.rest_vertices[t[0]], surf.rest_vertices[t[1]], surf.rest_vertices[t[2]]},
                       samples.barycentric[v]});
    of.push_back(v);
  }
  std::vector<SurfaceFitRow> fitted = surface_curvature_rows(nodes, points, normals, corners);
  std::vector<SurfaceFitRow> rows(want.size());
  for (std::size_t k = 0; k < of.size(); ++k) rows[of[k]] = std::move(fitted[k]);
  return rows;
}

}  // namespace

std::shared_ptr<const ContactSurface> build_contact_surface(const Scene& scene, const Body& body,
                                                            const Discretization& disc,
                                                            ContactSurfaceReport& report) {
  if (!body.surface)
    throw InputError(
        fmt::format("{}: key 'contact.surface': \"embedded\" needs a body with a surface", scene.file));
  const RenderSurface& surf = *body.surface;
  const ContactSpec& spec = scene.contact;
  auto out = std::make_shared<ContactSurface>();
  // The default: a third of the surface's mean edge, and on each triangle no coarser than a third of its own
  // mean edge, so that a graded lattice's fine window, under the tool, is sampled as densely as a uniform
  // lattice (docs/model/22-contact.md §22.5).
  constexpr double kEdgeFraction = 1.0 / 3.0;
  const bool asked = spec.sample_spacing_m > 0.0;
  out->sample_spacing_m = asked ? spec.sample_spacing_m : kEdgeFraction * mean_edge(surf);
  out->stiffness_pa_per_m = spec.stiffness_pa_per_m > 0.0
                                ? spec.stiffness_pa_per_m
                                : 100.0 * scene.material.youngs_modulus_pa / disc.mean_spacing();
  const SurfaceSamples samples = sample_surface(surf, out->sample_spacing_m, asked ? 0.0 : kEdgeFraction);
  const auto nv = samples.positions.size();

  // Which samples interpolate their triangle's nodes; the others take the MLS map.
  const std::vector<Index> node = node_at_vertex(surf, disc);
  std::vector<char> interp(nv, 0);
  Vec3Array mls_points;
  std::vector<std::size_t> mls_of;
  for (std::size_t v = 0; v < nv; ++v) {
    const auto& tri = surf.triangles[static_cast<std::size_t>(samples.triangle[v])];
    interp[v] = spec.shape_functions != ContactSpec::Shape::Mls && node[tri[0]] >= 0 && node[tri[1]] >= 0 &&
                node[tri[2]] >= 0;
    if (!interp[v]) {
      mls_of.push_back(v);
      mls_points.push_back(samples.positions[v]);
    }
  }
  std::unique_ptr<MlsMap> map;
  if (!mls_points.empty()) map = std::make_unique<MlsMap>(disc.rest_positions(), mls_points, scene.mapping);

  // "quadratic": the interpolating samples on smooth triangles take the fit instead, where it is conditioned.
  std::vector<SurfaceFitRow> quadratic;
  if (spec.shape_functions == ContactSpec::Shape::Quadratic) {
    std::vector<char> want(nv, 0);
    for (std::size_t v = 0; v < nv; ++v)
      want[v] = interp[v] && samples.smooth[v];  // a crease keeps its barycentric weights
    quadratic = curvature_rows(surf, samples, node, want);
  }

  out->rest_points = samples.positions;
  out->area_m2 = samples.area_m2;
  out->row_start.assign(nv + 1, 0);
  std::size_t m = 0;  // next MLS row
  for (std::size_t v = 0; v < nv; ++v) {
    if (interp[v]) {
      const auto& tri = surf.triangles[static_cast<std::size_t>(samples.triangle[v])];
      const std::size_t first = out->col.size();
      for (int k = 0; k < 3; ++k) {
        out->col.push_back(node[tri[k]]);
        out->val.push_back(samples.barycentric[v][k]);
      }
      if (!quadratic.empty() && !quadratic[v].node.empty()) {
        add_to_row(quadratic[v], first, out->col, out->val);
        ++report.quadratic;
      } else {
        ++report.interpolated;
      }
    } else {
      for (Index k = map->row_start()[m]; k < map->row_start()[m + 1]; ++k) {
        out->col.push_back(map->columns()[static_cast<std::size_t>(k)]);
        out->val.push_back(map->values()[static_cast<std::size_t>(k)]);
      }
      ++m;
    }
    out->row_start[v + 1] = static_cast<Index>(out->col.size());
  }
  // Nodes below the surface must not enter a tool either: a hard press can fold the outer layer past the next
  // one (a 0.5 mm block pressed 1 mm by a capsule across its edge did), and then nothing held the inner
  // nodes. Each node below the surface is a sample of its own (shape function 1 on itself, area mean
  // spacing^2); it acts only if that node enters a tool, which the surface's own samples prevent in an
  // ordinary press. The nodes on the surface (its vertices, a wall's outer and inner layers) are not: the
  // surface's samples are their contact, and with the MLS map's smoothed surface they would otherwise touch
  // the tool as nodes again.
  std::vector<char> on_surface(static_cast<std::size_t>(disc.num_nodes()), 0);
  for (Index i : node)
    if (i >= 0) on_surface[static_cast<std::size_t>(i)] = 1;
  if (body.wall)
    for (Index i = 0; i < disc.num_nodes(); ++i)
      if (body.wall->on_outer(i) || body.wall->on_inner(i)) on_surface[static_cast<std::size_t>(i)] = 1;
  const double node_area = disc.mean_spacing() * disc.mean_spacing();
  for (Index i = 0; i < disc.num_nodes(); ++i) {
    if (on_surface[static_cast<std::size_t>(i)]) continue;
    out->rest_points.push_back(disc.rest_positions()[i]);
    out->area_m2.push_back(node_area);
    out->col.push_back(i);
    out->val.push_back(1.0);
    out->row_start.push_back(static_cast<Index>(out->col.size()));
    ++report.node_samples;
  }
  out->finish();
  report.samples = static_cast<Index>(nv);
  report.spacing_m = out->sample_spacing_m;
  report.spacing_min_m = samples.spacing_min_m;
  report.stiffness_pa_per_m = out->stiffness_pa_per_m;
  return out;
}

}  // namespace vascsim
