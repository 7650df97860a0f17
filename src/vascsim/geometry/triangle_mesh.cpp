#include "vascsim/geometry/triangle_mesh.hpp"

#include "vascsim/geometry/vertex_normals.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <numbers>
#include <numeric>

#include "vascsim/core/error.hpp"

namespace vascsim {

namespace {

std::string fmt_vec(const Vec3& v) {
  return fmt::format("({:.6g}, {:.6g}, {:.6g})", v.x(), v.y(), v.z());
}

// Edge incidence of a mesh: every undirected edge once, with the triangles that use it.
struct EdgeTable {
  std::vector<std::array<Index, 2>> vertices;  // per edge, sorted (lo, hi)
  std::vector<std::array<Index, 2>> tris;      // per edge: the first two triangles (-1 if absent)
  std::vector<Index> tri_count;                // per edge: how many triangles use it
  std::vector<std::array<Index, 3>> of_tri;    // per triangle: edges (v0 v1), (v1 v2), (v2 v0)
};

// Sorting (key, slot) pairs instead of a hash map keeps the edge numbering deterministic.
EdgeTable build_edges(const TriangleMesh& m) {
  const std::size_t nf = m.triangles.size();
  std::vector<std::pair<std::uint64_t, std::uint64_t>> keyed;
  keyed.reserve(3 * nf);
  for (std::size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const auto a = static_cast<std::uint32_t>(m.triangles[f][k]);
      const auto b = static_cast<std::uint32_t>(m.triangles[f][(k + 1) % 3]);
      const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
      keyed.emplace_back(key, 3 * f + k);
    }
  std::sort(keyed.begin(), keyed.end());
  EdgeTable t;
  t.of_tri.resize(nf);
  for (std::size_t i = 0; i < keyed.size();) {
    std::size_t j = i;
    while (j < keyed.size() && keyed[j].first == keyed[i].first) ++j;
    const auto e = static_cast<Index>(t.vertices.size());
    t.vertices.push_back(
        {static_cast<Index>(keyed[i].first >> 32), static_cast<Index>(keyed[i].first & 0xffffffffu)});
    t.tris.push_back({static_cast<Index>(keyed[i].second / 3),
                      j - i > 1 ? static_cast<Index>(keyed[i + 1].second / 3) : -1});
    t.tri_count.push_back(static_cast<Index>(j - i));
    for (std::size_t q = i; q < j; ++q) t.of_tri[keyed[q].second / 3][keyed[q].second % 3] = e;
    i = j;
  }
  return t;
}

// True if triangle f traverses edge (a -> b) in that direction.
bool traverses(const Triangle& t, Index a, Index b) {
  for (int k = 0; k < 3; ++k)
    if (t[k] == a && t[(k + 1) % 3] == b) return true;
  return false;
}

// Breadth-first propagation of a consistent orientation over manifold edges. Returns per-triangle
// flip flags and component ids; `conflict` is the first triangle whose neighbours demand both
// orientations (a non-orientable surface), or -1.
struct Orientation {
  std::vector<char> flip;
  std::vector<Index> component;
  int count = 0;
  Index conflict = -1;
};

Orientation propagate_orientation(const TriangleMesh& m, const EdgeTable& edges) {
  const std::size_t nf = m.triangles.size();
  Orientation o;
  o.flip.assign(nf, 0);
  o.component.assign(nf, -1);
  std::deque<Index> queue;
  for (std::size_t seed = 0; seed < nf; ++seed) {
    if (o.component[seed] >= 0) continue;
    o.component[seed] = o.count;
    queue.push_back(static_cast<Index>(seed));
    while (!queue.empty()) {
      const Index f = queue.front();
      queue.pop_front();
      for (int k = 0; k < 3; ++k) {
        const Index e = edges.of_tri[f][k];
        if (edges.tri_count[e] != 2) continue;
        const Index g = edges.tris[e][0] == f ? edges.tris[e][1] : edges.tris[e][0];
        const Index a = m.triangles[f][k], b = m.triangles[f][(k + 1) % 3];
        // Neighbours agree when they run along the shared edge in opposite directions.
        const bool same_direction = traverses(m.triangles[g], a, b);
        const char want = static_cast<char>(o.flip[f] ^ (same_direction ? 1 : 0));
        if (o.component[g] < 0) {
          o.component[g] = o.count;
          o.flip[g] = want;
          queue.push_back(g);
        } else if (o.flip[g] != want && o.conflict < 0) {
          o.conflict = g;
        }
      }
    }
    ++o.count;
  }
  return o;
}

Vec3 tri_cross(const TriangleMesh& m, std::size_t f) {
  const auto& t = m.triangles[f];
  const Vec3& a = m.vertices[t[0]];
  return (m.vertices[t[1]] - a).cross(m.vertices[t[2]] - a);
}

// Generalised winding number of a closed oriented triangle set around p (1 inside, 0 outside), from
// the solid angles of the triangles (Van Oosterom & Strackee 1983).
double winding_number(const TriangleMesh& m, const std::vector<Index>& tris, const Vec3& p) {
  double omega = 0.0;
  for (const Index f : tris) {
    const auto& t = m.triangles[f];
    const Vec3 a = m.vertices[t[0]] - p, b = m.vertices[t[1]] - p, c = m.vertices[t[2]] - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    omega += 2.0 * std::atan2(num, den);
  }
  return omega / (4.0 * std::numbers::pi);
}

void flip_triangle(Triangle& t) {
  std::swap(t[1], t[2]);
}

}  // namespace

double bounding_box_diagonal(const TriangleMesh& mesh) {
  if (mesh.vertices.empty()) return 0.0;
  Eigen::AlignedBox3d box;
  for (const Vec3& v : mesh.vertices) box.extend(v);
  return box.diagonal().norm();
}

void check_mesh(const TriangleMesh& m, const std::string& name, bool require_closed) {
  auto fail = [&](const std::string& why) { throw InputError(name + ": " + why); };
  if (m.triangles.empty()) fail("no triangles (empty mesh)");
  const auto nv = static_cast<Index>(m.vertices.size());
  for (std::size_t f = 0; f < m.triangles.size(); ++f)
    for (const Index v : m.triangles[f])
      if (v < 0 || v >= nv) fail(fmt::format("triangle {} has vertex index {} outside [0, {})", f, v, nv));
  for (std::size_t v = 0; v < m.vertices.size(); ++v)
    if (!m.vertices[v].allFinite())
      fail(fmt::format("vertex {} has a non-finite coordinate {}", v, fmt_vec(m.vertices[v])));
  // The size scale of the degeneracy test: the bounding box of all vertices.
  const double diag = bounding_box_diagonal(m);
  const double min_area = 1e-12 * diag * diag;
  for (std::size_t f = 0; f < m.triangles.size(); ++f) {
    const auto& t = m.triangles[f];
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0])
      fail(fmt::format("degenerate triangle {}: repeated vertex index ({}, {}, {}) at {}", f, t[0], t[1],
                       t[2], fmt_vec(m.vertices[t[0]])));
    const double area = 0.5 * tri_cross(m, f).norm();
    if (!(area > min_area))
      fail(
          fmt::format("degenerate triangle {}: area {:.3g} m^2 <= 1e-12 * bbox diagonal^2 = {:.3g} m^2; "
                      "vertices {} {} {}",
                      f, area, min_area, fmt_vec(m.vertices[t[0]]), fmt_vec(m.vertices[t[1]]),
                      fmt_vec(m.vertices[t[2]])));
  }
  const EdgeTable edges = build_edges(m);
  for (std::size_t e = 0; e < edges.vertices.size(); ++e)
    if (edges.tri_count[e] > 2) {
      const auto [a, b] = edges.vertices[e];
      fail(fmt::format("non-manifold edge ({}, {}) from {} to {} is shared by {} triangles (first: {})", a, b,
                       fmt_vec(m.vertices[a]), fmt_vec(m.vertices[b]), edges.tri_count[e], edges.tris[e][0]));
    }
  const Orientation o = propagate_orientation(m, edges);
  if (o.conflict >= 0)
    fail(fmt::format("the surface cannot be oriented consistently (Moebius-like) near triangle {} at {}",
                     o.conflict, fmt_vec(m.vertices[m.triangles[o.conflict][0]])));
  if (require_closed) {
    std::size_t open = 0, first = 0;
    for (std::size_t e = 0; e < edges.vertices.size(); ++e)
      if (edges.tri_count[e] == 1 && open++ == 0) first = e;
    if (open > 0) {
      const auto [a, b] = edges.vertices[first];
      fail(
          fmt::format("the surface is open but must be closed: edge ({}, {}) from {} to {} of triangle {} "
                      "belongs to one triangle only ({} boundary edges in total)",
                      a, b, fmt_vec(m.vertices[a]), fmt_vec(m.vertices[b]), edges.tris[first][0], open));
    }
  }
}

MeshComponents orient_outward(TriangleMesh& m) {
  const EdgeTable edges = build_edges(m);
  const Orientation o = propagate_orientation(m, edges);
  for (std::size_t f = 0; f < m.triangles.size(); ++f)
    if (o.flip[f]) flip_triangle(m.triangles[f]);

  MeshComponents out;
  out.of_triangle = o.component;
  out.closed.assign(static_cast<std::size_t>(o.count), 1);
  out.nesting_depth.assign(static_cast<std::size_t>(o.count), 0);
  std::vector<std::vector<Index>> tris_of(static_cast<std::size_t>(o.count));
  for (std::size_t f = 0; f < m.triangles.size(); ++f)
    tris_of[o.component[f]].push_back(static_cast<Index>(f));
  for (std::size_t e = 0; e < edges.vertices.size(); ++e)
    if (edges.tri_count[e] == 1) out.closed[o.component[edges.tris[e][0]]] = 0;

  // Boundary loops (for the cap of open components): union-find over boundary-edge vertices.
  std::vector<Index> parent(m.vertices.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](Index v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  struct Directed {
    Index a, b, comp;
  };
  std::vector<Directed> open_edges;
  for (std::size_t e = 0; e < edges.vertices.size(); ++e) {
    if (edges.tri_count[e] != 1) continue;
    const Index f = edges.tris[e][0];
    const auto& t = m.triangles[f];
    for (int k = 0; k < 3; ++k)
      if (edges.of_tri[f][k] == static_cast<Index>(e))
        open_edges.push_back({t[k], t[(k + 1) % 3], o.component[f]});
    parent[root(edges.vertices[e][0])] = root(edges.vertices[e][1]);
  }
  std::vector<Vec3> loop_sum(m.vertices.size(), Vec3::Zero());
  std::vector<int> loop_n(m.vertices.size(), 0);
  for (const auto& d : open_edges) {
    loop_sum[root(d.a)] += m.vertices[d.a];
    ++loop_n[root(d.a)];
  }

  // Enclosed volume per component about the mesh centroid (less cancellation than the origin).
  Vec3 origin = Vec3::Zero();
  for (const Vec3& v : m.vertices) origin += v;
  origin /= std::max<std::size_t>(1, m.vertices.size());
  std::vector<double> volume(static_cast<std::size_t>(o.count), 0.0);
  for (std::size_t f = 0; f < m.triangles.size(); ++f) {
    const auto& t = m.triangles[f];
    volume[o.component[f]] +=
        (m.vertices[t[0]] - origin).dot((m.vertices[t[1]] - origin).cross(m.vertices[t[2]] - origin));
  }
  for (const auto& d : open_edges) {
    const Index r = root(d.a);
    const Vec3 q = loop_sum[r] / loop_n[r];
    volume[d.comp] += (m.vertices[d.b] - origin).dot((m.vertices[d.a] - origin).cross(q - origin));
  }
  for (int c = 0; c < o.count; ++c)
    if (volume[c] < 0.0)
      for (const Index f : tris_of[c]) flip_triangle(m.triangles[f]);

  // Nesting: a closed component inside an odd number of others bounds a cavity of the solid.
  for (int c = 0; c < o.count; ++c) {
    if (!out.closed[c]) continue;
    const Vec3& probe = m.vertices[m.triangles[tris_of[c].front()][0]];
    for (int d = 0; d < o.count; ++d)
      if (d != c && out.closed[d] && winding_number(m, tris_of[d], probe) > 0.5) ++out.nesting_depth[c];
  }
  for (int c = 0; c < o.count; ++c)
    if (out.nesting_depth[c] % 2 == 1)
      for (const Index f : tris_of[c]) flip_triangle(m.triangles[f]);
  return out;
}

double enclosed_volume(const TriangleMesh& m) {
  if (m.vertices.empty()) return 0.0;
  Vec3 origin = Vec3::Zero();
  for (const Vec3& v : m.vertices) origin += v;
  origin /= static_cast<double>(m.vertices.size());
  double six_v = 0.0;
  for (const auto& t : m.triangles)
    six_v += (m.vertices[t[0]] - origin).dot((m.vertices[t[1]] - origin).cross(m.vertices[t[2]] - origin));
  return six_v / 6.0;
}

std::vector<std::array<Index, 2>> boundary_edges(const TriangleMesh& m) {
  const EdgeTable edges = build_edges(m);
  std::vector<std::array<Index, 2>> out;
  for (std::size_t e = 0; e < edges.vertices.size(); ++e) {
    if (edges.tri_count[e] != 1) continue;
    const Index f = edges.tris[e][0];
    for (int k = 0; k < 3; ++k)
      if (edges.of_tri[f][k] == static_cast<Index>(e))
        out.push_back({m.triangles[f][k], m.triangles[f][(k + 1) % 3]});
  }
  return out;
}

// ----------------------------------------------------------------------------------------------
// MeshDistance

namespace {

// Closest point on triangle (a, b, c) to p by its Voronoi regions (Ericson, Real-Time Collision
// Detection, 2005, section 5.1.5). region: 0 face, 1..3 vertex a/b/c, 4 edge ab, 5 edge bc, 6 edge ca.
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, int& region) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) {
    region = 1;
    return a;
  }
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) {
    region = 2;
    return b;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    region = 4;
    return a + (d1 / (d1 - d3)) * ab;
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) {
    region = 3;
    return c;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    region = 6;
    return a + (d2 / (d2 - d6)) * ac;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
    region = 5;
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  }
  region = 0;
  const double inv = 1.0 / (va + vb + vc);
  return a + ab * (vb * inv) + ac * (vc * inv);
}

constexpr Index kLeafSize = 4;

}  // namespace

MeshDistance::MeshDistance(const TriangleMesh& mesh) : mesh_(mesh) {
  const std::size_t nf = mesh_.triangles.size();
  face_normal_.resize(nf);
  for (std::size_t f = 0; f < nf; ++f) face_normal_[f] = tri_cross(mesh_, f).normalized();
  const EdgeTable edges = build_edges(mesh_);
  tri_edge_ = edges.of_tri;
  // Edge pseudo-normal: both incident faces weigh pi, i.e. the plain sum (Baerentzen & Aanaes).
  edge_normal_.assign(edges.vertices.size(), Vec3::Zero());
  edge_boundary_.assign(edges.vertices.size(), 0);
  vertex_boundary_.assign(mesh_.vertices.size(), 0);
  for (std::size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) edge_normal_[tri_edge_[f][k]] += face_normal_[f];
  for (std::size_t e = 0; e < edges.vertices.size(); ++e) {
    edge_normal_[e].normalize();
    if (edges.tri_count[e] == 1) {
      edge_boundary_[e] = 1;
      vertex_boundary_[edges.vertices[e][0]] = vertex_boundary_[edges.vertices[e][1]] = 1;
    }
  }
  vertex_normal_ = vertex_normals(mesh_.triangles, mesh_.vertices);
  if (nf == 0) return;
  Vec3Array centroids(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    const auto& t = mesh_.triangles[f];
    centroids[f] = (mesh_.vertices[t[0]] + mesh_.vertices[t[1]] + mesh_.vertices[t[2]]) / 3.0;
  }
  order_.resize(nf);
  std::iota(order_.begin(), order_.end(), 0);
  nodes_.reserve(2 * nf / kLeafSize + 2);
  build(0, static_cast<Index>(nf), centroids);
}

// Median split along the longest axis of the centroids' box; leaves of <= kLeafSize triangles.
Index MeshDistance::build(Index begin, Index end, const Vec3Array& centroids) {
  const auto id = static_cast<Index>(nodes_.size());
  nodes_.emplace_back();
  Eigen::AlignedBox3d box, cbox;
  for (Index i = begin; i < end; ++i) {
    for (const Index v : mesh_.triangles[order_[i]]) box.extend(mesh_.vertices[v]);
    cbox.extend(centroids[order_[i]]);
  }
  nodes_[id].box = box;
  if (end - begin <= kLeafSize) {
    nodes_[id].first = begin;
    nodes_[id].count = end - begin;
    return id;
  }
  int axis = 0;
  cbox.diagonal().maxCoeff(&axis);
  const Index mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](Index x, Index y) { return centroids[x][axis] < centroids[y][axis]; });
  const Index left = build(begin, mid, centroids);
  const Index right = build(mid, end, centroids);
  nodes_[id].first = left;
  nodes_[id].right = right;
  return id;
}

ClosestPoint MeshDistance::closest(const Vec3& p, double max_distance) const {
  ClosestPoint best;
  if (nodes_.empty()) return best;
  double best2 = max_distance * max_distance;  // inf stays inf
  int best_region = 0;
  Index stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (node.box.squaredExteriorDistance(p) > best2) continue;
    if (node.count > 0) {
      for (Index i = node.first; i < node.first + node.count; ++i) {
        const Index f = order_[i];
        const auto& t = mesh_.triangles[f];
        int region = 0;
        const Vec3 q =
            closest_on_triangle(p, mesh_.vertices[t[0]], mesh_.vertices[t[1]], mesh_.vertices[t[2]], region);
        const double d2 = (p - q).squaredNorm();
        if (d2 < best2 || (!best.found && d2 <= best2)) {
          best2 = d2;
          best.found = true;
          best.point = q;
          best.triangle = f;
          best_region = region;
        }
      }
      continue;
    }
    const double dl = nodes_[node.first].box.squaredExteriorDistance(p);
    const double dr = nodes_[node.right].box.squaredExteriorDistance(p);
    // Push the farther child first so the nearer one is searched first and tightens the bound.
    const bool left_first = dl <= dr;
    const Index near_child = left_first ? node.first : node.right,
                far_child = left_first ? node.right : node.first;
    const double dnear = std::min(dl, dr), dfar = std::max(dl, dr);
    if (dfar <= best2 && top < 127) stack[top++] = far_child;
    if (dnear <= best2 && top < 127) stack[top++] = near_child;
  }
  if (!best.found) return best;
  const Index f = best.triangle;
  const auto& t = mesh_.triangles[f];
  if (best_region == 0) {
    best.feature = MeshFeature::face;
    best.normal = face_normal_[f];
  } else if (best_region <= 3) {
    const Index v = t[best_region - 1];
    best.feature = MeshFeature::vertex;
    best.normal = vertex_normal_[v];
    best.on_boundary = vertex_boundary_[v] != 0;
  } else {
    // regions 4, 5, 6 are the edges (v0 v1), (v1 v2), (v2 v0) = tri_edge_ slots 0, 1, 2
    const Index e = tri_edge_[f][best_region - 4];
    best.feature = MeshFeature::edge;
    best.normal = edge_normal_[e];
    best.on_boundary = edge_boundary_[e] != 0;
  }
  best.distance = std::sqrt(best2);
  best.signed_distance = (p - best.point).dot(best.normal) < 0.0 ? -best.distance : best.distance;
  return best;
}

}  // namespace vascsim
