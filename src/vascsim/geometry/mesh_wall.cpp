#include "vascsim/geometry/mesh_wall.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <unordered_map>

#include "vascsim/core/error.hpp"
#include "vascsim/core/spatial_grid.hpp"
#include "vascsim/core/stopwatch.hpp"
#include "vascsim/geometry/kuhn.hpp"
#include "vascsim/geometry/vertex_normals.hpp"

namespace vascsim {

namespace {

constexpr double kMaxLatticePoints = 5e7;
constexpr double kNegInf = -std::numeric_limits<double>::infinity();
// The lattice origin is shifted by this fraction of Delta so that lattice planes avoid the round
// coordinates common in CAD and test meshes (a node exactly on the surface makes inside/outside a
// coin flip decided by rounding).
constexpr double kLatticeShift = 0.3183;
// A tet edge or centroid may graze the lumen (or the outside) by this fraction of Delta: a chord of
// length sqrt(3) Delta sags 3 Delta^2 / (8 R) into a lumen of radius R, <= 0.1 Delta for R >= 3.75
// Delta. An edge that crosses a narrow lumen or gap goes deeper and its tet is dropped.
constexpr double kEdgeGrazeFraction = 0.1;
// Snap band (isosurface stuffing, Labelle & Shewchuk 2007, with the Kuhn split instead of their BCC
// stencils): a lattice point inside the solid within kSnapInside Delta of a wall surface, or outside
// it within kSnapOutside Delta, is moved onto the closest surface point. The band is 1.5 cells wide,
// so every normal line through a surface meets a snapped point; an unsnapped (interior) point stays
// >= Delta / 2 from every surface, hence from every snapped node. Snapping outside points up to a
// whole cell (not only Delta / 2) keeps the cells that straddle the surface obliquely: with Delta / 2
// the closed tube lost 3-8 % of its volume, with Delta 0.3-2 % (1.5 Delta gained < 0.5 % more).
constexpr double kSnapInside = 0.5;
constexpr double kSnapOutside = 1.0;
// Snapped nodes closer than this fraction of Delta are merged into the first one (lattice order):
// where the snap band is nearly parallel to a lattice plane, or at creases and ridges, two lattice
// points can snap to (almost) the same surface point, and coincident nodes break the MLS
// discretisation. Also the guaranteed minimum node spacing.
constexpr double kMergeFraction = 0.3;
// Kept tets need quality 6 sqrt(2) V / l_rms^3 (1 for the regular tet, 0.657 for a Kuhn tet) at least
// this. It bounds the shape-function gradients in the linear tet stiffness (the quasi-static
// preconditioner) and the XPBD tet constraints; the slivers it removes are flattened cells against the
// surface and hold little volume.
constexpr double kMinQuality = 0.1;

// 6 sqrt(2) V / l_rms^3: 1 for the regular tetrahedron, -> 0 for every degenerate shape (sliver,
// needle, cap, wedge), negative when inverted.
double tet_quality(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double l2 = ((b - a).squaredNorm() + (c - a).squaredNorm() + (d - a).squaredNorm() +
                     (c - b).squaredNorm() + (d - b).squaredNorm() + (d - c).squaredNorm()) /
                    6.0;
  return l2 > 0.0 ? 6.0 * std::sqrt(2.0) * signed_volume(a, b, c, d) / (l2 * std::sqrt(l2)) : 0.0;
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
  const std::vector<char>* triangle_is_inner = nullptr;  // closed_wall: per surface triangle

  double slack(const Vec3& q) const {
    if (closed_wall) return -surface->signed_distance(q);
    const ClosestPoint cp = surface->closest(q, t + delta);
    if (!cp.found || (open && cp.on_boundary)) return kNegInf;
    return std::min(cp.signed_distance, t - cp.signed_distance);
  }

  // Per lattice point: dropped, interior (kept where it is) or snapped onto the lumen/inner or the
  // outer surface; the node position, its depth from the lumen/inner surface and the direction away
  // from it.
  enum class State : std::uint8_t { out, interior, inner, outer };
  struct NodeInfo {
    State state = State::out;
    Vec3 pos = Vec3::Zero();
    double slack = kNegInf;
    double depth = 0.0;
    Vec3 outward = Vec3::Zero();
  };
  NodeInfo node(const Vec3& q) const {
    NodeInfo n;
    const double band = kSnapInside * delta;
    const ClosestPoint cp = closed_wall ? surface->closest(q) : surface->closest(q, t + delta);
    if (!cp.found) return n;
    if (closed_wall) {
      const double slack = -cp.signed_distance;
      if (slack < -kSnapOutside * delta) return n;
      if (slack >= band) {
        n.state = State::interior;
        n.pos = q;
        n.slack = slack;
      } else {
        n.pos = cp.point;
        n.slack = 0.0;
        n.state = (*triangle_is_inner)[static_cast<std::size_t>(cp.triangle)] ? State::inner : State::outer;
        if (n.state == State::inner) {
          // Away from the lumen = into the solid = against the solid's outward normal.
          n.outward = cp.distance > 1e-9 * delta
                          ? Vec3((slack >= 0.0 ? q - cp.point : cp.point - q) / cp.distance)
                          : Vec3(-cp.normal);
          return n;  // depth exactly 0
        }
      }
      const ClosestPoint ci = inner->closest(n.pos);
      n.depth = ci.distance;
      // Inner normals face the lumen; away from it is minus the pseudo-normal on the surface itself.
      n.outward = ci.distance > 1e-9 * delta ? Vec3((n.pos - ci.point) / ci.distance) : Vec3(-ci.normal);
      return n;
    }
    if (open && cp.on_boundary) return n;  // beyond an opening: the wall is clipped there
    const double sd = cp.signed_distance;
    if (sd < -kSnapOutside * delta || sd > t + kSnapOutside * delta) return n;
    // The closest-point ray from the lumen through q: the depth along it is the distance to the lumen.
    n.outward = cp.distance > 1e-9 * delta ? Vec3((sd >= 0.0 ? q - cp.point : cp.point - q) / cp.distance)
                                           : cp.normal;
    if (sd < band) {
      n.state = State::inner;
      n.pos = cp.point;
      n.slack = 0.0;
    } else if (sd >= t - band) {
      // The closest point on the offset surface {distance = t} lies on the same ray, at depth t.
      n.state = State::outer;
      n.pos = cp.point + t * n.outward;
      n.depth = t;
      n.slack = 0.0;
    } else {
      n.state = State::interior;
      n.pos = q;
      n.depth = sd;
      n.slack = std::min(sd, t - sd);
    }
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
  const Vec3Array n = vertex_normals(lumen.triangles, lumen.vertices);
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

// The lattice the wall nodes come from: spacing delta, `dims` points per axis from `origin`.
struct Lattice {
  Vec3 origin = Vec3::Zero();
  double delta = 0.0;
  Eigen::Array3d dims_real = Eigen::Array3d::Zero();
  std::int64_t nx = 0, ny = 0, nz = 0;
  double total() const { return dims_real.prod(); }
  std::int64_t id(std::int64_t i, std::int64_t j, std::int64_t k) const { return i + nx * (j + ny * k); }
  Vec3 point(std::int64_t id) const {
    const std::int64_t i = id % nx, j = (id / nx) % ny, k = id / (nx * ny);
    return Vec3(origin +
                delta * Vec3(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k)));
  }
};

[[noreturn]] void fail(const std::string& source, const std::string& what) {
  throw InputError(source + ": " + what);
}

void check_spec(const MeshWallSpec& spec) {
  const std::string& name = spec.source;
  if (spec.kind != "lumen" && spec.kind != "closed_wall")
    fail(name, fmt::format("mesh wall kind '{}' is unknown; use \"lumen\" or \"closed_wall\"", spec.kind));
  if (spec.min_layers < 2)
    fail(name,
         "min_layers must be >= 2 (3 or more recommended, docs/model/00-design-decisions.md, decision 2)");
  if (!(std::isfinite(spec.node_spacing_m) && spec.node_spacing_m > 0.0))
    fail(name, "node_spacing_m must be finite and > 0");
  if (spec.kind == "lumen" && !(std::isfinite(spec.wall_thickness_m) && spec.wall_thickness_m > 0.0))
    fail(name, "wall_thickness_m must be finite and > 0");
}

// closed_wall: the inner (odd nesting depth) components of an oriented mesh, and the thinnest wall between
// them and the outer ones.
double split_closed_wall(const TriangleMesh& mesh, const MeshComponents& comps, const std::string& name,
                         TriangleMesh& inner_mesh) {
  TriangleMesh outer_mesh;
  inner_mesh.vertices = outer_mesh.vertices = mesh.vertices;
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
    (comps.nesting_depth[comps.of_triangle[f]] % 2 ? inner_mesh : outer_mesh)
        .triangles.push_back(mesh.triangles[f]);
  if (inner_mesh.triangles.empty())
    fail(name,
         fmt::format("closed_wall needs an inner surface inside the outer one, but none of the {} closed "
                     "components lies inside another (use kind \"lumen\" for a lumen surface)",
                     comps.count()));
  const double t = thinnest_wall(inner_mesh, outer_mesh);
  if (!(t > 0.0)) fail(name, "the inner and outer surfaces touch (thinnest wall 0)");
  return t;
}

// The lattice over the mesh box, padded by `pad` (the wall lies outside a lumen).
Lattice make_lattice(const TriangleMesh& mesh, double pad, double delta, const std::string& name) {
  Eigen::AlignedBox3d box;
  for (const auto& tri : mesh.triangles)
    for (const Index v : tri) box.extend(mesh.vertices[v]);
  Lattice L;
  L.delta = delta;
  L.origin = box.min() - Vec3::Constant(pad + kLatticeShift * delta);
  const Vec3 extent = box.max() + Vec3::Constant(pad) - L.origin;
  L.dims_real = (extent / delta).array().floor() + 2.0;
  if (!(L.total() <= kMaxLatticePoints))
    fail(name, fmt::format(
                   "the lattice at spacing {:.4g} m would have {:.3g} points; the limit is {:.0g} (increase "
                   "node_spacing_m or wall_thickness_m)",
                   delta, L.total(), kMaxLatticePoints));
  const Eigen::Vector3i dims = L.dims_real.cast<int>().matrix();
  L.nx = dims[0];
  L.ny = dims[1];
  L.nz = dims[2];
  return L;
}

// "lumen": the lattice points within `reach` of some triangle's box (a band that holds the wall and its
// snap band), in lattice order.
std::vector<std::int64_t> band_candidates(const TriangleMesh& mesh, const Lattice& L, double reach) {
  std::vector<char> mark(static_cast<std::size_t>(L.total()), 0);
  for (const auto& tri : mesh.triangles) {
    Eigen::AlignedBox3d tb;
    for (const Index v : tri) tb.extend(mesh.vertices[v]);
    const Eigen::Array3d lo = ((tb.min().array() - reach - L.origin.array()) / L.delta).ceil().max(0.0);
    const Eigen::Array3d hi =
        ((tb.max().array() + reach - L.origin.array()) / L.delta).floor().min(L.dims_real - 1.0);
    for (auto k = static_cast<std::int64_t>(lo[2]); k <= static_cast<std::int64_t>(hi[2]); ++k)
      for (auto j = static_cast<std::int64_t>(lo[1]); j <= static_cast<std::int64_t>(hi[1]); ++j)
        for (auto i = static_cast<std::int64_t>(lo[0]); i <= static_cast<std::int64_t>(hi[0]); ++i)
          mark[static_cast<std::size_t>(L.id(i, j, k))] = 1;
  }
  std::vector<std::int64_t> candidates;
  for (std::size_t c = 0; c < mark.size(); ++c)
    if (mark[c]) candidates.push_back(static_cast<std::int64_t>(c));
  return candidates;
}

// The lattice points of the solid and its snap band, with their snapped positions.
struct LatticeNodes {
  std::vector<Index> node_of;  // per lattice point: node, -1 none
  std::vector<std::int64_t> lattice;
  std::vector<double> slack, depth;
  std::vector<WallSolid::State> state;
  Vec3Array pos, outward;
  std::int64_t size() const { return static_cast<std::int64_t>(lattice.size()); }
};

// Evaluated in parallel chunks (bounded memory), numbered serially in lattice order (deterministic for any
// thread count). `candidates` empty: every lattice point.
LatticeNodes collect_nodes(const WallSolid& solid, const Lattice& L,
                           const std::vector<std::int64_t>& candidates, bool all_points) {
  using State = WallSolid::State;
  LatticeNodes nodes;
  nodes.node_of.assign(static_cast<std::size_t>(L.total()), -1);
  constexpr std::int64_t kChunk = 1 << 16;
  std::vector<WallSolid::NodeInfo> info(static_cast<std::size_t>(kChunk));
  const auto ncand =
      all_points ? static_cast<std::int64_t>(L.total()) : static_cast<std::int64_t>(candidates.size());
  auto candidate = [&](std::int64_t c) { return all_points ? c : candidates[static_cast<std::size_t>(c)]; };
  for (std::int64_t c0 = 0; c0 < ncand; c0 += kChunk) {
    const std::int64_t c1 = std::min(ncand, c0 + kChunk);
#pragma omp parallel for schedule(dynamic, 256)
    for (std::int64_t c = c0; c < c1; ++c) info[c - c0] = solid.node(L.point(candidate(c)));
    for (std::int64_t c = c0; c < c1; ++c) {
      const auto& n = info[c - c0];
      if (n.state == State::out) continue;
      const std::int64_t id = candidate(c);
      nodes.node_of[static_cast<std::size_t>(id)] = static_cast<Index>(nodes.lattice.size());
      nodes.lattice.push_back(id);
      nodes.pos.push_back(n.pos);
      nodes.state.push_back(n.state);
      nodes.slack.push_back(n.slack);
      nodes.depth.push_back(n.depth);
      nodes.outward.push_back(n.outward);
    }
  }
  return nodes;
}

// Merges snapped nodes closer than kMergeFraction Delta into the first of them (lattice order, so
// deterministic): an unsnapped node is >= Delta / 2 from any surface and lattice points are Delta apart, so
// only snapped pairs can come close. A hash of cells of edge r_merge finds them. Returns the alias of every
// node (itself, or the node it merged into) and counts the merges.
std::vector<Index> merge_snapped_nodes(const LatticeNodes& nodes, const Lattice& L, std::int64_t& merged) {
  const std::int64_t nn = nodes.size();
  std::vector<Index> alias(static_cast<std::size_t>(nn));
  merged = 0;
  const double r_merge = kMergeFraction * L.delta;
  auto key = [&](const Eigen::Vector3i& c) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(c[0])) * 73856093u) ^
           (static_cast<std::uint64_t>(static_cast<std::uint32_t>(c[1])) * 19349663u) ^
           (static_cast<std::uint64_t>(static_cast<std::uint32_t>(c[2])) * 83492791u);
  };
  std::unordered_map<std::uint64_t, std::vector<Index>> cells;
  for (std::int64_t n = 0; n < nn; ++n) {
    alias[n] = static_cast<Index>(n);
    if (nodes.state[n] == WallSolid::State::interior) continue;
    const Eigen::Vector3i c = ((nodes.pos[n] - L.origin) / r_merge).array().floor().cast<int>().matrix();
    Index rep = -1;
    for (int dz = -1; dz <= 1 && rep < 0; ++dz)
      for (int dy = -1; dy <= 1 && rep < 0; ++dy)
        for (int dx = -1; dx <= 1 && rep < 0; ++dx) {
          const auto it = cells.find(key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == cells.end()) continue;
          for (const Index m : it->second)
            if ((nodes.pos[m] - nodes.pos[n]).norm() < r_merge) {
              rep = m;
              break;
            }
        }
    if (rep >= 0) {
      alias[n] = rep;
      ++merged;
    } else {
      cells[key(c)].push_back(static_cast<Index>(n));
    }
  }
  return alias;
}

// The eight corner nodes (after merging) of the lattice cell whose lowest corner is node n; -1 where the
// cell leaves the lattice or a corner is no node.
std::array<Index, 8> cell_corners(const LatticeNodes& nodes, const Lattice& L,
                                  const std::vector<Index>& alias, std::int64_t n) {
  std::array<Index, 8> corner;
  corner.fill(-1);
  const std::int64_t id = nodes.lattice[n];
  const std::int64_t i = id % L.nx, j = (id / L.nx) % L.ny, k = id / (L.nx * L.ny);
  if (i + 1 >= L.nx || j + 1 >= L.ny || k + 1 >= L.nz) return corner;
  for (int m = 0; m < 8; ++m) {
    const Index v =
        nodes.node_of[static_cast<std::size_t>(L.id(i + (m & 1), j + ((m >> 1) & 1), k + ((m >> 2) & 1)))];
    corner[m] = v < 0 ? v : alias[v];
  }
  return corner;
}

// The Kuhn tets of the lattice cells, with the snapped and merged vertex positions, that the wall keeps: four
// distinct nodes, quality >= kMinQuality (so positively oriented), the centroid inside the solid and no edge
// leaving the solid by more than kEdgeGrazeFraction Delta at its midpoint (so no tet spans the lumen or a gap
// between walls; both up to the chord sag of a curved surface). The Lipschitz bound skips the midpoint query
// when an endpoint is deep enough: slack(mid) >= slack(end) - |edge| / 2. Counts the low-quality drops.
std::vector<Tet> keep_tets(const WallSolid& solid, const LatticeNodes& nodes, const Lattice& L,
                           const std::vector<Index>& alias, std::int64_t& dropped_low_quality) {
  const auto kuhn = positive_kuhn_tets();
  const double graze = kEdgeGrazeFraction * L.delta;
  const std::int64_t nn = nodes.size();
  std::vector<std::uint8_t> keep(static_cast<std::size_t>(nn), 0);
  std::vector<std::int64_t> low_quality(static_cast<std::size_t>(nn), 0);
  const Vec3Array& pos = nodes.pos;
#pragma omp parallel for schedule(dynamic, 256)
  for (std::int64_t n = 0; n < nn; ++n) {
    const std::array<Index, 8> corner = cell_corners(nodes, L, alias, n);
    if (corner[0] < 0 || corner[7] < 0 || corner[0] == corner[7]) continue;
    std::uint8_t mask = 0;
    for (std::size_t q = 0; q < kuhn.size(); ++q) {
      const auto& tk = kuhn[q];
      const Tet tet{corner[tk[0]], corner[tk[1]], corner[tk[2]], corner[tk[3]]};
      if (std::min({tet[0], tet[1], tet[2], tet[3]}) < 0) continue;
      if (tet[0] == tet[1] || tet[0] == tet[2] || tet[0] == tet[3] || tet[1] == tet[2] || tet[1] == tet[3] ||
          tet[2] == tet[3])
        continue;  // collapsed by a merge
      const Vec3 &a = pos[tet[0]], &b = pos[tet[1]], &c = pos[tet[2]], &d = pos[tet[3]];
      if (tet_quality(a, b, c, d) < kMinQuality) {
        ++low_quality[n];
        continue;
      }
      if (solid.slack(0.25 * (a + b + c + d)) < -graze) continue;
      bool ok = true;
      for (int u = 0; u < 4 && ok; ++u)
        for (int v = u + 1; v < 4 && ok; ++v) {
          const double half = 0.5 * (pos[tet[u]] - pos[tet[v]]).norm();
          if (std::max(nodes.slack[tet[u]], nodes.slack[tet[v]]) - half >= -graze) continue;
          ok = solid.slack(0.5 * (pos[tet[u]] + pos[tet[v]])) >= -graze;
        }
      if (ok) mask = static_cast<std::uint8_t>(mask | (1u << q));
    }
    keep[n] = mask;
  }
  std::vector<Tet> tets;
  for (std::int64_t n = 0; n < nn; ++n) {
    if (!keep[n]) continue;
    const std::array<Index, 8> corner = cell_corners(nodes, L, alias, n);
    for (std::size_t q = 0; q < kuhn.size(); ++q)
      if (keep[n] & (1u << q))
        tets.push_back({corner[kuhn[q][0]], corner[kuhn[q][1]], corner[kuhn[q][2]], corner[kuhn[q][3]]});
  }
  dropped_low_quality = 0;
  for (const auto c : low_quality) dropped_low_quality += c;
  return tets;
}

// The node cloud of the kept tets: only nodes a tet uses, renumbered in lattice order, with their wall
// coordinates.
void build_wall_cloud(const LatticeNodes& nodes, std::vector<Tet> tets, double delta, MeshWall& w) {
  using State = WallSolid::State;
  std::vector<Index> renumber(static_cast<std::size_t>(nodes.size()), -1);
  for (const Tet& tet : tets)
    for (const Index v : tet) renumber[v] = 0;
  NodeCloud& cloud = w.cloud;
  for (std::int64_t n = 0; n < nodes.size(); ++n) {
    if (renumber[n] < 0) continue;
    renumber[n] = static_cast<Index>(cloud.positions.size());
    cloud.positions.push_back(nodes.pos[n]);
    w.depth_m.push_back(nodes.depth[n]);
    w.outward.push_back(nodes.outward[n]);
    w.node_surface.push_back(nodes.state[n] == State::inner ? 1 : nodes.state[n] == State::outer ? 2 : 0);
    cloud.box.extend(nodes.pos[n]);
  }
  for (Tet& tet : tets)
    for (Index& v : tet) v = renumber[v];
  cloud.tets = std::move(tets);
  cloud.kind = "mesh_wall";
  cloud.spacing_m = delta;
}

// The render surface: a closed wall's own surfaces, or a lumen's wall (lumen_wall_surface).
void build_wall_surface(const TriangleMesh& mesh, const MeshComponents& comps, bool closed_wall, double t,
                        const std::string& name, MeshWall& w) {
  if (closed_wall) {
    w.triangles = mesh.triangles;
    w.surface_vertices = mesh.vertices;
    w.normals = vertex_normals(mesh.triangles, mesh.vertices);
    w.surface_is_outer.assign(mesh.vertices.size(), 0);
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
      if (comps.nesting_depth[comps.of_triangle[f]] % 2 == 0)
        for (const Index v : mesh.triangles[f]) w.surface_is_outer[v] = 1;
    return;
  }
  lumen_wall_surface(mesh, t, w);
  // The fold-overs touch only the drawn outer surface (the nodes and the mechanics are the wall's own). A few
  // local ones, where a real segmentation's lumen bends tighter than the wall is thick, are information;
  // above 1 % of the triangles the picture is visibly wrong and the user should know.
  if (w.outer_foldovers > 0) {
    const bool many =
        static_cast<double>(w.outer_foldovers) > 0.01 * static_cast<double>(mesh.triangles.size());
    spdlog::log(many ? spdlog::level::warn : spdlog::level::info,
                "{}: {} of {} outer-surface triangles fold over (the lumen curves tighter than the wall "
                "thickness {:.4g} m there); the rendering surface self-intersects locally",
                name, w.outer_foldovers, mesh.triangles.size(), t);
  }
}

}  // namespace

MeshWall make_mesh_wall(const TriangleMesh& input, const MeshWallSpec& spec) {
  const Stopwatch clock;
  const std::string& name = spec.source;
  check_spec(spec);
  const bool closed_wall = spec.kind == "closed_wall";
  check_mesh(input, name, closed_wall);
  TriangleMesh mesh = input;
  const MeshComponents comps = orient_outward(mesh);
  const bool open = std::any_of(comps.closed.begin(), comps.closed.end(), [](char c) { return !c; });

  MeshWall w;
  TriangleMesh inner_mesh;
  const double t = closed_wall ? split_closed_wall(mesh, comps, name, inner_mesh) : spec.wall_thickness_m;
  // Delta = t / min_layers: with nodes snapped onto both surfaces an axis-aligned wall holds
  // min_layers + 1 node planes. t / (min_layers - 1) (min_layers planes, as the swept vessel) measured
  // min_layers - 1 in places on the aorta (measure_wall_layers: where a surface's snapped nodes were
  // merged or their tets dropped, the depth span within Delta of the normal line falls short of t);
  // t / min_layers measured >= min_layers on the tubes at every axis direction and on the aorta.
  const double delta = std::min(spec.node_spacing_m, t / spec.min_layers);
  w.thickness_m = t;
  w.nominal_layers = static_cast<int>(std::floor(t / delta + 1e-9)) + 1;
  const Lattice lattice = make_lattice(mesh, (closed_wall ? 0.0 : t) + delta, delta, name);

  const MeshDistance surface(mesh);
  std::optional<MeshDistance> inner;
  if (closed_wall) inner.emplace(inner_mesh);
  std::vector<char> triangle_is_inner(mesh.triangles.size(), 0);
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
    triangle_is_inner[f] = closed_wall && comps.nesting_depth[comps.of_triangle[f]] % 2 == 1;
  const WallSolid solid{&surface, inner ? &*inner : nullptr, closed_wall, open, t, delta, &triangle_is_inner};

  // Candidates: for "lumen", the band around the triangles; for "closed_wall" every lattice point (the solid
  // may be thick).
  const std::vector<std::int64_t> candidates =
      closed_wall ? std::vector<std::int64_t>{} : band_candidates(mesh, lattice, t + delta);
  const LatticeNodes nodes = collect_nodes(solid, lattice, candidates, closed_wall);
  std::int64_t merged = 0, dropped_low_quality = 0;
  const std::vector<Index> alias = merge_snapped_nodes(nodes, lattice, merged);
  std::vector<Tet> tets = keep_tets(solid, nodes, lattice, alias, dropped_low_quality);
  if (tets.empty())
    fail(name,
         fmt::format("the wall keeps no tetrahedron at lattice spacing {:.4g} m (wall thickness {:.4g} m); "
                     "decrease node_spacing_m",
                     delta, t));
  build_wall_cloud(nodes, std::move(tets), delta, w);
  build_wall_surface(mesh, comps, closed_wall, t, name, w);
  spdlog::info(
      "{}: mesh wall ({}{}): {} nodes ({} snapped nodes merged), {} tets ({} below quality {} dropped), "
      "lattice spacing {:.4g} m, wall {:.4g} m, {} nominal layers, {:.2f} s",
      name, spec.kind, open ? ", open ends" : "", w.cloud.positions.size(), merged, w.cloud.tets.size(),
      dropped_low_quality, kMinQuality, delta, t, w.nominal_layers, clock.seconds());
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
