#include "vascsim/geometry/mesh_wall.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

#include "vascsim/core/error.hpp"
#include "vascsim/core/spatial_grid.hpp"

namespace vascsim {

namespace {

constexpr double kMaxLatticePoints = 5e7;
constexpr double kNegInf = -std::numeric_limits<double>::infinity();
// The lattice origin is shifted by this fraction of Delta so that lattice planes avoid the round
// coordinates common in CAD and test meshes (a node exactly on the surface makes inside/outside a
// coin flip decided by rounding).
constexpr double kLatticeShift = 0.3183;
// A tet edge may graze the lumen (or the outside) by this fraction of Delta: a chord of length
// sqrt(3) Delta sags 3 Delta^2 / (8 R) into a lumen of radius R, <= 0.1 Delta for R >= 3.75 Delta.
// An edge that crosses a narrow lumen or gap goes deeper and its tet is dropped.
constexpr double kEdgeGrazeFraction = 0.1;

// Kuhn split of a lattice cube as corner bit masks (bit a = +1 along axis a); every tet contains the
// corners 0 and 7, so a cube is only visited from a kept lower corner.
constexpr std::array<std::array<int, 4>, 6> kKuhnTets = {{
    {0, 1, 3, 7},
    {0, 1, 5, 7},
    {0, 2, 3, 7},
    {0, 2, 6, 7},
    {0, 4, 5, 7},
    {0, 4, 6, 7},
}};

// Corner orders with positive volume on an axis-aligned lattice of positive spacing.
std::array<std::array<int, 4>, 6> positive_kuhn_tets() {
  auto corner = [](int m) { return Vec3(m & 1, (m >> 1) & 1, (m >> 2) & 1); };
  auto tets = kKuhnTets;
  for (auto& t : tets)
    if (signed_volume(corner(t[0]), corner(t[1]), corner(t[2]), corner(t[3])) < 0.0) std::swap(t[2], t[3]);
  return tets;
}

// The wall solid as a "slack" function: >= 0 inside, and 1-Lipschitz (min of distance functions),
// so slack(a) - |a - b| bounds slack(b) and lets the tet filter skip most edge queries.
struct WallSolid {
  const MeshDistance* surface = nullptr;  // oriented: normals point out of the lumen / out of the solid
  const MeshDistance* inner = nullptr;    // closed_wall: the inner (odd-depth) components only
  bool closed_wall = false;
  bool open = false;  // lumen with boundary loops: clip at the openings
  double t = 0.0;
  double delta = 0.0;

  double slack(const Vec3& q) const {
    if (closed_wall) return -surface->signed_distance(q);
    const ClosestPoint cp = surface->closest(q, t + delta);
    if (!cp.found || (open && cp.on_boundary)) return kNegInf;
    return std::min(cp.signed_distance, t - cp.signed_distance);
  }

  // Per lattice point: inside?, depth from the lumen/inner surface and the direction away from it.
  struct NodeInfo {
    bool inside = false;
    double slack = kNegInf;
    double depth = 0.0;
    Vec3 outward = Vec3::Zero();
  };
  NodeInfo node(const Vec3& q) const {
    NodeInfo n;
    const ClosestPoint cp = closed_wall ? surface->closest(q) : surface->closest(q, t + delta);
    if (!cp.found) return n;
    if (closed_wall) {
      n.slack = -cp.signed_distance;
      if (n.slack < 0.0) return n;
      const ClosestPoint ci = inner->closest(q);
      n.depth = ci.distance;
      // Inner normals face the lumen; away from it is minus the pseudo-normal on the surface itself.
      n.outward = ci.distance > 1e-9 * delta ? Vec3((q - ci.point) / ci.distance) : Vec3(-ci.normal);
    } else {
      if (open && cp.on_boundary) return n;
      n.slack = std::min(cp.signed_distance, t - cp.signed_distance);
      if (n.slack < 0.0) return n;
      n.depth = cp.signed_distance;
      n.outward = cp.distance > 1e-9 * delta ? Vec3((q - cp.point) / cp.distance) : cp.normal;
    }
    n.inside = true;
    return n;
  }
};

// The thinnest wall of a closed-wall mesh, measured at the vertices: each inner-surface vertex's
// distance to the outer surface and each outer-surface vertex's distance to the inner one, m.
double thinnest_wall(const TriangleMesh& inner, const TriangleMesh& outer) {
  const MeshDistance to_inner(inner), to_outer(outer);
  double t = std::numeric_limits<double>::infinity();
  auto scan = [&t](const TriangleMesh& from, const MeshDistance& to) {
    std::vector<char> used(from.vertices.size(), 0);
    for (const auto& tri : from.triangles)
      for (const Index v : tri) used[v] = 1;
    for (std::size_t v = 0; v < used.size(); ++v)
      if (used[v]) t = std::min(t, to.closest(from.vertices[v]).distance);
  };
  scan(inner, to_outer);
  scan(outer, to_inner);
  return t;
}

// Wall surface for kind "lumen": the lumen flipped (normals into the lumen), its offset by t along the
// vertex normals, and rim strips along the boundary loops of an open lumen.
void lumen_wall_surface(const TriangleMesh& lumen, double t, MeshWall& w) {
  const Vec3Array n = vertex_normals(lumen);
  const auto nv = static_cast<Index>(lumen.vertices.size());
  w.surface_vertices.resize(2 * static_cast<std::size_t>(nv));
  w.normals.resize(w.surface_vertices.size());
  w.surface_is_outer.assign(w.surface_vertices.size(), 0);
  for (Index v = 0; v < nv; ++v) {
    w.surface_vertices[v] = lumen.vertices[v];
    w.normals[v] = -n[v];
    w.surface_vertices[nv + v] = lumen.vertices[v] + t * n[v];
    w.normals[nv + v] = n[v];
    w.surface_is_outer[nv + v] = 1;
  }
  for (const auto& tri : lumen.triangles) {
    w.triangles.push_back({tri[0], tri[2], tri[1]});
    w.triangles.push_back({nv + tri[0], nv + tri[1], nv + tri[2]});
    const auto& a = lumen.vertices;
    const auto& b = w.surface_vertices;
    const Vec3 n_in = (a[tri[1]] - a[tri[0]]).cross(a[tri[2]] - a[tri[0]]);
    const Vec3 n_out = (b[nv + tri[1]] - b[nv + tri[0]]).cross(b[nv + tri[2]] - b[nv + tri[0]]);
    if (n_in.dot(n_out) <= 0.0) ++w.outer_foldovers;
  }
  // Boundary edge a -> b of the lumen: the flipped inner copy runs b -> a and the outer copy a' -> b',
  // so the quad (a, b, b', a') closes the gap with consistent orientation.
  for (const auto& [a, b] : boundary_edges(lumen)) {
    w.triangles.push_back({a, b, nv + b});
    w.triangles.push_back({a, nv + b, nv + a});
  }
}

}  // namespace

MeshWall make_mesh_wall(const TriangleMesh& input, const MeshWallSpec& spec) {
  const auto start = std::chrono::steady_clock::now();
  const std::string& name = spec.source;
  auto require = [&](bool ok, const std::string& what) {
    if (!ok) throw InputError(name + ": " + what);
  };
  require(spec.kind == "lumen" || spec.kind == "closed_wall",
          fmt::format("mesh wall kind '{}' is unknown; use \"lumen\" or \"closed_wall\"", spec.kind));
  const bool closed_wall = spec.kind == "closed_wall";
  require(spec.min_layers >= 2, "min_layers must be >= 2 (MODEL.md decision 2 asks for >= 3)");
  require(std::isfinite(spec.node_spacing_m) && spec.node_spacing_m > 0.0,
          "node_spacing_m must be finite and > 0");
  if (!closed_wall)
    require(std::isfinite(spec.wall_thickness_m) && spec.wall_thickness_m > 0.0,
            "wall_thickness_m must be finite and > 0");
  check_mesh(input, name, closed_wall);

  TriangleMesh mesh = input;
  const MeshComponents comps = orient_outward(mesh);
  const bool open = std::any_of(comps.closed.begin(), comps.closed.end(), [](char c) { return !c; });

  MeshWall w;
  TriangleMesh inner_mesh;
  double t = spec.wall_thickness_m;
  if (closed_wall) {
    TriangleMesh outer_mesh;
    inner_mesh.vertices = outer_mesh.vertices = mesh.vertices;
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
      (comps.nesting_depth[comps.of_triangle[f]] % 2 ? inner_mesh : outer_mesh)
          .triangles.push_back(mesh.triangles[f]);
    require(!inner_mesh.triangles.empty(),
            fmt::format("closed_wall needs an inner surface inside the outer one, but none of the {} closed "
                        "components lies inside another (use kind \"lumen\" for a lumen surface)",
                        comps.count()));
    t = thinnest_wall(inner_mesh, outer_mesh);
    require(t > 0.0, "the inner and outer surfaces touch (thinnest wall 0)");
  }
  // Half a layer of margin: at Delta = t / min_layers the lattice fits min_layers planes across an
  // axis-aligned wall, but nodes whose cubes are cut by a curved surface are dropped and oblique walls
  // then measured min_layers - 1 in places (measure_wall_layers on tubes at several axis directions);
  // t / (min_layers + 0.25) was the smallest margin measured to reach min_layers everywhere.
  const double delta = std::min(spec.node_spacing_m, t / (spec.min_layers + 0.5));
  w.thickness_m = t;
  w.nominal_layers = static_cast<int>(std::floor(t / delta + 1e-9)) + 1;

  // Lattice over the mesh box, padded by the wall for "lumen" (the wall lies outside the lumen).
  Eigen::AlignedBox3d box;
  for (const auto& tri : mesh.triangles)
    for (const Index v : tri) box.extend(mesh.vertices[v]);
  const double pad = (closed_wall ? 0.0 : t) + delta;
  const Vec3 origin = box.min() - Vec3::Constant(pad + kLatticeShift * delta);
  const Vec3 extent = box.max() + Vec3::Constant(pad) - origin;
  const Eigen::Array3d dims_real = (extent / delta).array().floor() + 2.0;
  const double total = dims_real.prod();
  require(
      total <= kMaxLatticePoints,
      fmt::format("the lattice at spacing {:.4g} m would have {:.3g} points; the limit is {:.0g} (increase "
                  "node_spacing_m or wall_thickness_m)",
                  delta, total, kMaxLatticePoints));
  const Eigen::Vector3i dims = dims_real.cast<int>().matrix();
  const auto nx = static_cast<std::int64_t>(dims[0]), ny = static_cast<std::int64_t>(dims[1]),
             nz = static_cast<std::int64_t>(dims[2]);
  auto lattice_id = [&](std::int64_t i, std::int64_t j, std::int64_t k) { return i + nx * (j + ny * k); };
  auto lattice_point = [&](std::int64_t id) {
    const std::int64_t i = id % nx, j = (id / nx) % ny, k = id / (nx * ny);
    return Vec3(origin +
                delta * Vec3(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k)));
  };

  const MeshDistance surface(mesh);
  std::optional<MeshDistance> inner;
  if (closed_wall) inner.emplace(inner_mesh);
  WallSolid solid{&surface, inner ? &*inner : nullptr, closed_wall, open, t, delta};

  // Candidates: for "lumen", lattice points within t of some triangle's box (a narrow band); for
  // "closed_wall" every lattice point (the solid may be thick somewhere).
  std::vector<std::int64_t> candidates;
  if (!closed_wall) {
    std::vector<char> mark(static_cast<std::size_t>(total), 0);
    for (const auto& tri : mesh.triangles) {
      Eigen::AlignedBox3d tb;
      for (const Index v : tri) tb.extend(mesh.vertices[v]);
      const Eigen::Array3d lo = ((tb.min().array() - t - origin.array()) / delta).ceil().max(0.0);
      const Eigen::Array3d hi =
          ((tb.max().array() + t - origin.array()) / delta).floor().min(dims_real - 1.0);
      for (auto k = static_cast<std::int64_t>(lo[2]); k <= static_cast<std::int64_t>(hi[2]); ++k)
        for (auto j = static_cast<std::int64_t>(lo[1]); j <= static_cast<std::int64_t>(hi[1]); ++j)
          for (auto i = static_cast<std::int64_t>(lo[0]); i <= static_cast<std::int64_t>(hi[0]); ++i)
            mark[static_cast<std::size_t>(lattice_id(i, j, k))] = 1;
    }
    for (std::size_t c = 0; c < mark.size(); ++c)
      if (mark[c]) candidates.push_back(static_cast<std::int64_t>(c));
  }

  // Nodes: lattice points inside the solid, evaluated in parallel chunks (bounded memory), numbered
  // serially in lattice order (deterministic for any thread count).
  std::vector<Index> node_of(static_cast<std::size_t>(total), -1);
  std::vector<std::int64_t> node_lattice;
  std::vector<double> node_slack, node_depth;
  Vec3Array node_pos, node_out;
  constexpr std::int64_t kChunk = 1 << 16;
  std::vector<WallSolid::NodeInfo> info(static_cast<std::size_t>(kChunk));
  const auto ncand =
      closed_wall ? static_cast<std::int64_t>(total) : static_cast<std::int64_t>(candidates.size());
  auto candidate = [&](std::int64_t c) { return closed_wall ? c : candidates[static_cast<std::size_t>(c)]; };
  for (std::int64_t c0 = 0; c0 < ncand; c0 += kChunk) {
    const std::int64_t c1 = std::min(ncand, c0 + kChunk);
#pragma omp parallel for schedule(dynamic, 256)
    for (std::int64_t c = c0; c < c1; ++c) info[c - c0] = solid.node(lattice_point(candidate(c)));
    for (std::int64_t c = c0; c < c1; ++c) {
      const auto& n = info[c - c0];
      if (!n.inside) continue;
      const std::int64_t id = candidate(c);
      node_of[static_cast<std::size_t>(id)] = static_cast<Index>(node_lattice.size());
      node_lattice.push_back(id);
      node_pos.push_back(lattice_point(id));
      node_slack.push_back(n.slack);
      node_depth.push_back(n.depth);
      node_out.push_back(n.outward);
    }
  }

  // Tets: a Kuhn tet is kept when its four vertices are nodes, its centroid is inside the solid, and
  // no edge leaves the solid by more than kEdgeGrazeFraction Delta at its midpoint (so no tet spans
  // the lumen or a gap between walls). The Lipschitz bound skips the midpoint query when an endpoint
  // is deep enough: slack(mid) >= slack(end) - |edge| / 2.
  const auto kuhn = positive_kuhn_tets();
  const double graze = kEdgeGrazeFraction * delta;
  const auto nn = static_cast<std::int64_t>(node_lattice.size());
  std::vector<std::uint8_t> keep(static_cast<std::size_t>(nn), 0);
#pragma omp parallel for schedule(dynamic, 256)
  for (std::int64_t n = 0; n < nn; ++n) {
    const std::int64_t id = node_lattice[n];
    const std::int64_t i = id % nx, j = (id / nx) % ny, k = id / (nx * ny);
    if (i + 1 >= nx || j + 1 >= ny || k + 1 >= nz) continue;
    std::array<Index, 8> corner;
    for (int m = 0; m < 8; ++m)
      corner[m] =
          node_of[static_cast<std::size_t>(lattice_id(i + (m & 1), j + ((m >> 1) & 1), k + ((m >> 2) & 1)))];
    if (corner[7] < 0) continue;
    std::uint8_t mask = 0;
    for (std::size_t q = 0; q < kuhn.size(); ++q) {
      const auto& tk = kuhn[q];
      const Tet tet{corner[tk[0]], corner[tk[1]], corner[tk[2]], corner[tk[3]]};
      if (std::min({tet[0], tet[1], tet[2], tet[3]}) < 0) continue;
      const Vec3 centroid =
          0.25 * (node_pos[tet[0]] + node_pos[tet[1]] + node_pos[tet[2]] + node_pos[tet[3]]);
      if (solid.slack(centroid) < 0.0) continue;
      bool ok = true;
      for (int a = 0; a < 4 && ok; ++a)
        for (int b = a + 1; b < 4 && ok; ++b) {
          const double half = 0.5 * (node_pos[tet[a]] - node_pos[tet[b]]).norm();
          if (std::max(node_slack[tet[a]], node_slack[tet[b]]) - half >= -graze) continue;
          ok = solid.slack(0.5 * (node_pos[tet[a]] + node_pos[tet[b]])) >= -graze;
        }
      if (ok) mask = static_cast<std::uint8_t>(mask | (1u << q));
    }
    keep[n] = mask;
  }

  // Keep only nodes used by a kept tet, renumbered in lattice order.
  std::vector<Tet> tets;
  for (std::int64_t n = 0; n < nn; ++n) {
    if (!keep[n]) continue;
    const std::int64_t id = node_lattice[n];
    const std::int64_t i = id % nx, j = (id / nx) % ny, k = id / (nx * ny);
    for (std::size_t q = 0; q < kuhn.size(); ++q) {
      if (!(keep[n] & (1u << q))) continue;
      Tet tet;
      for (int c = 0; c < 4; ++c) {
        const int m = kuhn[q][c];
        tet[c] = node_of[static_cast<std::size_t>(
            lattice_id(i + (m & 1), j + ((m >> 1) & 1), k + ((m >> 2) & 1)))];
      }
      tets.push_back(tet);
    }
  }
  require(!tets.empty(),
          fmt::format("the wall keeps no tetrahedron at lattice spacing {:.4g} m (wall thickness "
                      "{:.4g} m); decrease node_spacing_m",
                      delta, t));
  std::vector<Index> renumber(static_cast<std::size_t>(nn), -1);
  for (const Tet& tet : tets)
    for (const Index v : tet) renumber[v] = 0;
  NodeCloud& cloud = w.cloud;
  for (std::int64_t n = 0; n < nn; ++n) {
    if (renumber[n] < 0) continue;
    renumber[n] = static_cast<Index>(cloud.positions.size());
    cloud.positions.push_back(node_pos[n]);
    w.depth_m.push_back(node_depth[n]);
    w.outward.push_back(node_out[n]);
    cloud.box.extend(node_pos[n]);
  }
  for (Tet& tet : tets)
    for (Index& v : tet) v = renumber[v];
  cloud.tets = std::move(tets);
  cloud.kind = "mesh_wall";
  cloud.spacing_m = delta;

  if (closed_wall) {
    w.triangles = mesh.triangles;
    w.surface_vertices = mesh.vertices;
    w.normals = vertex_normals(mesh);
    w.surface_is_outer.assign(mesh.vertices.size(), 0);
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
      if (comps.nesting_depth[comps.of_triangle[f]] % 2 == 0)
        for (const Index v : mesh.triangles[f]) w.surface_is_outer[v] = 1;
  } else {
    lumen_wall_surface(mesh, t, w);
    if (w.outer_foldovers > 0)
      spdlog::warn(
          "{}: {} of {} outer-surface triangles fold over (the lumen curves tighter than the wall "
          "thickness {:.4g} m there); the rendering surface self-intersects locally",
          name, w.outer_foldovers, mesh.triangles.size(), t);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  spdlog::info(
      "{}: mesh wall ({}{}): {} nodes, {} tets, lattice spacing {:.4g} m, wall {:.4g} m, {} nominal "
      "layers, {:.2f} s",
      name, spec.kind, open ? ", open ends" : "", cloud.positions.size(), cloud.tets.size(), delta, t,
      w.nominal_layers, seconds);
  return w;
}

WallLayers measure_wall_layers(const MeshWall& w, int max_samples) {
  WallLayers out;
  const auto& X = w.cloud.positions;
  if (X.size() < 2 || max_samples <= 0) return out;
  const double delta = w.cloud.spacing_m, t = w.thickness_m;
  const SpatialGrid grid(X, delta);
  std::vector<Index> inner;
  for (std::size_t v = 0; v < w.surface_vertices.size(); ++v)
    if (!w.surface_is_outer[v]) inner.push_back(static_cast<Index>(v));
  if (inner.empty()) return out;
  const std::size_t stride = std::max<std::size_t>(1, inner.size() / static_cast<std::size_t>(max_samples));
  out.min = std::numeric_limits<int>::max();
  double sum = 0.0;
  for (std::size_t s = 0; s < inner.size() && out.samples < max_samples; s += stride) {
    const Vec3 p = w.surface_vertices[inner[s]];
    const Vec3 n = -w.normals[inner[s]];
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    grid.for_each_within(p + 0.5 * t * n, std::hypot(0.5 * t + delta, delta), [&](Index j, double) {
      const Vec3 d = X[j] - p;
      const double along = d.dot(n);
      if (along < -delta || along > t + delta || (d - along * n).norm() > delta) return;
      lo = std::min(lo, along);
      hi = std::max(hi, along);
    });
    const int layers = hi >= lo ? static_cast<int>(std::floor((hi - lo) / delta + 1e-6)) + 1 : 0;
    out.min = std::min(out.min, layers);
    sum += layers;
    ++out.samples;
  }
  out.mean = sum / out.samples;
  return out;
}

}  // namespace vascsim
