#include "vascsim/viewer/surface_snapshot.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "vascsim/core/error.hpp"
#include "vascsim/core/parallel.hpp"
#include "vascsim/core/stopwatch.hpp"

namespace vascsim::viewer {

namespace {

// Length per unit u over length per unit v on the outer wall (the median over its triangles): the procedural
// texture then has square cells. Triangles across the v seam are skipped; 1 without uv.
float uv_aspect_of(const RenderSurface& s) {
  if (s.uv.empty()) return 1.0f;
  std::vector<double> ratios;
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    if (!s.outer.empty() && s.outer[t] == 0) continue;
    const auto& tri = s.triangles[t];
    const Eigen::Vector2d d1 = s.uv[tri[1]] - s.uv[tri[0]], d2 = s.uv[tri[2]] - s.uv[tri[0]];
    if (std::abs(d1.y()) > 0.5 || std::abs(d2.y()) > 0.5) continue;
    const double det = d1.x() * d2.y() - d1.y() * d2.x();
    if (std::abs(det) < 1e-14) continue;
    const Vec3 e1 = s.rest_vertices[tri[1]] - s.rest_vertices[tri[0]],
               e2 = s.rest_vertices[tri[2]] - s.rest_vertices[tri[0]];
    const Vec3 du = (d2.y() * e1 - d1.y() * e2) / det, dv = (-d2.x() * e1 + d1.x() * e2) / det;
    if (dv.norm() > 0.0) ratios.push_back(du.norm() / dv.norm());
  }
  if (ratios.empty()) return 1.0f;
  std::nth_element(ratios.begin(), ratios.begin() + static_cast<std::ptrdiff_t>(ratios.size() / 2),
                   ratios.end());
  return static_cast<float>(ratios[ratios.size() / 2]);
}

// Imported walls have no (u, v): the texture is wrapped around the patient's superior axis through the
// surface's centroid (v: the angle around it, u: the height over the mean circumference, so its cells are
// square). Branches get a skewed but continuous texture.
std::vector<render::Float2> cylindrical_uv(const Vec3Array& vertices, const Vec3& superior) {
  Vec3 c = Vec3::Zero();
  for (const Vec3& p : vertices) c += p;
  c /= static_cast<double>(std::max<std::size_t>(vertices.size(), 1));
  const Vec3 a = superior.normalized();
  const Vec3 e1 = a.unitOrthogonal(), e2 = a.cross(e1);
  double radius = 0.0;
  for (const Vec3& p : vertices) radius += ((p - c) - (p - c).dot(a) * a).norm();
  const double circumference =
      2.0 * std::numbers::pi *
      std::max(radius / static_cast<double>(std::max<std::size_t>(vertices.size(), 1)), 1e-12);
  std::vector<render::Float2> uv;
  uv.reserve(vertices.size());
  for (const Vec3& p : vertices) {
    const Vec3 d = p - c;
    const double v = std::atan2(d.dot(e2), d.dot(e1)) / (2.0 * std::numbers::pi);
    uv.emplace_back(static_cast<float>(d.dot(a) / circumference), static_cast<float>(v < 0.0 ? v + 1.0 : v));
  }
  return uv;
}

// Per vertex: on the outer wall if one of its triangles is (all of them without flags).
std::vector<std::uint8_t> outer_vertices(const RenderSurface& s) {
  std::vector<std::uint8_t> outer(s.rest_vertices.size(), s.outer.empty() ? 1 : 0);
  for (std::size_t t = 0; t < s.outer.size(); ++t)
    if (s.outer[t] != 0)
      for (const Index v : s.triangles[t]) outer[static_cast<std::size_t>(v)] = 1;
  return outer;
}

}  // namespace

void fill_rest_surface(const RenderSurface& s, const Vec3& superior, render::RenderFrame& frame) {
  render::assign_positions(frame, s.rest_vertices);
  render::assign_normals(frame, s.rest_normals);
  frame.triangles.clear();
  for (const auto& t : s.triangles)
    frame.triangles.push_back({static_cast<std::uint32_t>(t[0]), static_cast<std::uint32_t>(t[1]),
                               static_cast<std::uint32_t>(t[2])});
  frame.uv.clear();
  for (const auto& uv : s.uv) frame.uv.push_back(uv.cast<float>());
  if (frame.uv.empty()) frame.uv = cylindrical_uv(s.rest_vertices, superior);
  frame.outer = outer_vertices(s);
  frame.uv_aspect = s.uv.empty() ? 1.0f : uv_aspect_of(s);
  ++frame.topology_version;
}

void SurfaceSnapshot::rebuild(Simulation& simulation, std::uint64_t build) {
  const Body& body = simulation.body();
  if (!body.surface)
    throw InputError(fmt::format("{}: geometry '{}' has no render surface to show", simulation.scene().file,
                                 simulation.scene().geometry.type));
  map_ = simulation.surface_map();
  build_ = build;
  const RenderSurface& s = *body.surface;
  triangles_.clear();
  for (const auto& t : s.triangles)
    triangles_.push_back({static_cast<std::uint32_t>(t[0]), static_cast<std::uint32_t>(t[1]),
                          static_cast<std::uint32_t>(t[2])});
  const std::size_t nv = s.rest_vertices.size();
  rest_.resize(nv);
  for (std::size_t v = 0; v < nv; ++v) rest_[v] = s.rest_vertices[v].cast<float>();
  uv_.clear();
  for (const auto& uv : s.uv) uv_.push_back(uv.cast<float>());
  if (uv_.empty()) uv_ = cylindrical_uv(s.rest_vertices, simulation.scene().viewer.superior);
  outer_ = outer_vertices(s);
  uv_aspect_ = s.uv.empty() ? 1.0f : uv_aspect_of(s);
  if (nv > 0) lo_ = hi_ = s.rest_vertices.front();
  for (const Vec3& p : s.rest_vertices) lo_ = lo_.cwiseMin(p), hi_ = hi_.cwiseMax(p);
  tet_edges_.clear();
}

bool SurfaceSnapshot::fill(Simulation& simulation, render::RenderFrame& frame, PrepareTiming& timing) {
  const Vec3Array& x = simulation.model().positions();
  const Vec3Array& X = simulation.discretization().rest_positions();
  displacement_.resize(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!x[i].allFinite()) return false;
    displacement_[i] = (x[i] - X[i]).cast<float>();
  }
  Stopwatch clock;
  map_->map_displacements_f32(displacement_, frame.positions_m);
  timing.map_ms = 1e3 * clock.seconds();
  clock.restart();
  render::compute_normals(frame.positions_m, triangles_, frame.normals);
  timing.normals_ms = 1e3 * clock.seconds();

  if (frame.topology_version != build_) {
    frame.topology_version = build_;
    frame.triangles = triangles_;
    frame.uv = uv_;
    frame.outer = outer_;
    frame.uv_aspect = uv_aspect_;
  }
  if (!frame.scalar) frame.scalar.emplace();
  render::ScalarField& d = *frame.scalar;
  d.values.resize(rest_.size());
  float largest = 0.0f;
  for (std::size_t v = 0; v < rest_.size(); ++v) {
    d.values[v] = 1e3f * (frame.positions_m[v] - rest_[v]).norm();
    largest = std::max(largest, d.values[v]);
  }
  d.min = 0.0f;
  d.max = std::max(largest, 1e-6f);
  d.label = "displacement";
  d.unit = "mm";
  return true;
}

void SurfaceSnapshot::fill_stress(Simulation& simulation, render::RenderFrame& frame) {
  const Material& m = simulation.scene().material;
  const double E = m.youngs_modulus_pa, nu = m.poisson_ratio;
  const double lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), mu = E / (2.0 * (1.0 + nu));
  const Vec3Array& x = simulation.model().positions();
  const Discretization& disc = simulation.discretization();
  const auto n = static_cast<Index>(x.size());
  node_stress_.resize(x.size());
#pragma omp parallel for schedule(static) if (n >= kParallelMinNodes)
  for (Index i = 0; i < n; ++i) {
    const Mat3 F = disc.deformation_gradient(i, x);
    const Mat3 G = 0.5 * (F.transpose() * F - Mat3::Identity());
    const Mat3 S = lambda * G.trace() * Mat3::Identity() + 2.0 * mu * G;
    const double J = F.determinant();
    const Mat3 sigma = F * S * F.transpose() / (std::abs(J) > 1e-12 ? J : 1.0);
    const Mat3 dev = sigma - sigma.trace() / 3.0 * Mat3::Identity();
    node_stress_[static_cast<std::size_t>(i)] = Vec3(std::sqrt(1.5 * dev.squaredNorm()), 0.0, 0.0);
  }
  map_->map_displacements(node_stress_, surface_stress_);  // linear in the nodal values: any field maps alike
  render::ScalarField& f = *frame.scalar;
  float largest = 0.0f;
  for (std::size_t v = 0; v < f.values.size(); ++v) {
    f.values[v] = static_cast<float>(std::max(0.0, 1e-3 * surface_stress_[v].x()));
    largest = std::max(largest, f.values[v]);
  }
  f.min = 0.0f;
  f.max = std::max(largest, 1e-9f);
  f.label = "von Mises stress";
  f.unit = "kPa";
}

void SurfaceSnapshot::fill_overlays(Simulation& simulation, bool nodes, bool tets,
                                    render::RenderFrame& frame) {
  frame.node_points_m.clear();
  frame.tet_edges.clear();
  if (!nodes && !tets) return;
  const Vec3Array& x = simulation.model().positions();
  frame.node_points_m.reserve(x.size());
  for (const Vec3& p : x) frame.node_points_m.push_back(p.cast<float>());
  if (!tets) return;
  if (tet_edges_.empty()) tet_edges_ = render::tet_edge_list(simulation.body().cloud.tets);
  frame.tet_edges = tet_edges_;
}

}  // namespace vascsim::viewer
