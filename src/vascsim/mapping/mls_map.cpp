#include "vascsim/mapping/mls_map.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "vascsim/core/error.hpp"
#include "vascsim/core/kernels.hpp"
#include "vascsim/core/spatial_grid.hpp"

namespace vascsim {

namespace {

using Vec4 = Eigen::Vector4d;
using Mat4 = Eigen::Matrix4d;

// Below this many rows a mat-vec takes microseconds and thread start-up would dominate.
constexpr Index kParallelRows = 4096;

// One surface vertex at one trial radius: its support, weights, scaled moment matrix and verdict.
struct Trial {
  std::vector<Index> nodes;
  std::vector<double> w;
  Mat4 A = Mat4::Zero();
  double cond = std::numeric_limits<double>::infinity();
};

// Scaled, shifted linear basis p^(Y) = [1, (Y - S)/r] (docs/model/20-mls-map.md): p^(S) = e1 and every entry
// of p^(X_i) is in [-1, 1], so A^ is O(1) whatever the coordinates' offset and unit.
Vec4 basis(const Vec3& y, const Vec3& s, double r) {
  Vec4 p;
  p << 1.0, (y - s) / r;
  return p;
}

Trial evaluate(const Vec3Array& X, const Vec3& s, double r, const SpatialGrid& grid) {
  Trial t;
  grid.for_each_within(s, r, [&](Index j, double) { t.nodes.push_back(j); });
  std::sort(t.nodes.begin(), t.nodes.end());
  t.w.reserve(t.nodes.size());
  for (Index j : t.nodes) {
    const double w = kernels::cubic_spline((X[j] - s).norm() / r);  // Eq. 37
    t.w.push_back(w);
    const Vec4 p = basis(X[j], s, r);
    t.A.noalias() += w * p * p.transpose();
  }
  if (t.nodes.size() >= 4) {
    // cond of the SPD 4x4 from its eigenvalues; a determinant test would miss a coplanar support.
    Eigen::SelfAdjointEigenSolver<Mat4> es(t.A, Eigen::EigenvaluesOnly);
    const Vec4 ev = es.eigenvalues();  // ascending
    if (ev[0] > 0.0) t.cond = ev[3] / ev[0];
  }
  return t;
}

bool passes(const Trial& t, const MlsMapOptions& opt) {
  return static_cast<int>(t.nodes.size()) >= opt.min_nodes && t.cond <= opt.cond_limit;
}

// The most growths the scene allows (mapping.max_growths is read in [0, 20]).
constexpr int kMaxGrowthsTried = 20;

// The smallest max_growths with which every failed vertex passes (0: none up to kMaxGrowthsTried does), so
// the guard's message can name a value that works.
int growths_needed(const Vec3Array& X, const Vec3Array& surface, const std::vector<char>& failed, double r0,
                   const MlsMapOptions& opt, const SpatialGrid& grid) {
  int needed = 0;
  for (std::size_t v = 0; v < surface.size(); ++v) {
    if (!failed[v]) continue;
    int g = opt.max_growths + 1;
    double r = r0 * std::pow(opt.growth_factor, g);
    while (g <= kMaxGrowthsTried && !passes(evaluate(X, surface[v], r, grid), opt)) {
      ++g;
      r *= opt.growth_factor;
    }
    if (g > kMaxGrowthsTried) return 0;
    needed = std::max(needed, g);
  }
  return needed;
}

// The options' ranges and finite, distinct points; InputError otherwise.
void check_inputs(const Vec3Array& nodes, const Vec3Array& surface, const MlsMapOptions& opt) {
  if (!(opt.support_radius_factor > 0.0) || !std::isfinite(opt.support_radius_factor))
    throw InputError("MLS map: support_radius_factor must be > 0");
  if (opt.min_nodes < 4) throw InputError("MLS map: min_nodes must be >= 4 (a linear basis has 4 terms)");
  if (!(opt.cond_limit >= 1.0)) throw InputError("MLS map: cond_limit must be >= 1");
  if (!(opt.growth_factor > 1.0)) throw InputError("MLS map: growth_factor must be > 1");
  if (opt.max_growths < 0) throw InputError("MLS map: max_growths must be >= 0");
  if (nodes.size() < 4)
    throw InputError(fmt::format("MLS map: {} nodes; at least 4 are needed", nodes.size()));
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (!nodes[i].allFinite()) throw InputError(fmt::format("MLS map: node {} is not finite", i));
  for (std::size_t v = 0; v < surface.size(); ++v)
    if (!surface[v].allFinite()) throw InputError(fmt::format("MLS map: surface vertex {} is not finite", v));
}

// Every vertex's support, grown from r0 by growth_factor until the guard passes or max_growths is spent.
struct SupportSearch {
  std::vector<Trial> trials;
  std::vector<int> growths;
  std::vector<char> failed;
  std::vector<double> radius;
};

SupportSearch search_supports(const Vec3Array& X, const Vec3Array& surface, double r0,
                              const SpatialGrid& grid, const MlsMapOptions& opt) {
  const Index nv = static_cast<Index>(surface.size());
  SupportSearch found{std::vector<Trial>(nv), std::vector<int>(nv, 0), std::vector<char>(nv, 0),
                      std::vector<double>(nv, r0)};
#pragma omp parallel for schedule(dynamic, 64)
  for (Index v = 0; v < nv; ++v) {
    double r = r0;
    for (int g = 0;; ++g) {
      found.trials[v] = evaluate(X, surface[v], r, grid);
      found.growths[v] = g;
      if (passes(found.trials[v], opt)) break;
      if (g == opt.max_growths) {
        found.failed[v] = 1;
        break;
      }
      r *= opt.growth_factor;
    }
    found.radius[v] = r;
  }
  return found;
}

// The guard's message for the first failed vertex, with the value of mapping.max_growths that fixes it.
[[noreturn]] void throw_guard_failure(const Vec3Array& X, const Vec3Array& surface,
                                      const SupportSearch& found, Index v, double r0, const SpatialGrid& grid,
                                      const MlsMapOptions& opt) {
  const auto n_failed = std::count(found.failed.begin(), found.failed.end(), char{1});
  const Vec3& s = surface[v];
  const int needed = growths_needed(X, surface, found.failed, r0, opt, grid);
  const std::string growth =
      needed > 0
          ? fmt::format(
                "let the support grow further: mapping.max_growths = {} makes every vertex pass (now {})",
                needed, opt.max_growths)
          : fmt::format(
                "even {} growths do not help: the nodes near it are too few or coplanar (a single node "
                "layer through the wall?): use more node layers or keep the surface within about one "
                "spacing of the nodes",
                kMaxGrowthsTried);
  // A lattice too coarse for its wall is fixed by a finer one: growths would make it run, inaccurately.
  const std::string fix =
      opt.coarse_spacing_advice.empty()
          ? growth
          : fmt::format("{}; {}{}", opt.coarse_spacing_advice, needed > 0 ? "or " : "", growth);
  throw NumericalError(fmt::format(
      "MLS map: surface vertex {} at ({:.6g}, {:.6g}, {:.6g}) m has {} nodes in its support and cond(A^) "
      "{:.3g} at support radius {:.4g} m after {} growths (need >= {} nodes and cond <= {:.3g}; {} of {} "
      "vertices "
      "fail): {}",
      v, s.x(), s.y(), s.z(), found.trials[v].nodes.size(), found.trials[v].cond, found.radius[v],
      opt.max_growths, opt.min_nodes, opt.cond_limit, n_failed, surface.size(), fix));
}

}  // namespace

MlsMap::MlsMap(const Vec3Array& rest_nodes_m, const Vec3Array& rest_surface_m, const MlsMapOptions& opt)
    : rest_nodes_(rest_nodes_m), rest_surface_(rest_surface_m) {
  check_inputs(rest_nodes_, rest_surface_, opt);
  const double spacing = mean_nearest_spacing(rest_nodes_);
  if (!(spacing > 0.0)) throw InputError("MLS map: the nodes coincide (mean nearest spacing is zero)");
  const double r0 = opt.support_radius_factor * spacing;
  SpatialGrid grid(rest_nodes_, r0);

  const SupportSearch found = search_supports(rest_nodes_, rest_surface_, r0, grid, opt);
  const auto failed = std::find(found.failed.begin(), found.failed.end(), char{1});
  if (failed != found.failed.end())
    throw_guard_failure(rest_nodes_, rest_surface_, found, static_cast<Index>(failed - found.failed.begin()),
                        r0, grid, opt);
  radius_ = found.radius;

  const Index nv = num_vertices();
  row_start_.assign(static_cast<std::size_t>(nv) + 1, 0);
  for (Index v = 0; v < nv; ++v)
    row_start_[v + 1] = row_start_[v] + static_cast<Index>(found.trials[v].nodes.size());
  const std::size_t nnz = static_cast<std::size_t>(row_start_[nv]);
  col_.resize(nnz);
  val_.resize(nnz);
  val_f32_.resize(nnz);
  cond_.assign(nv, 0.0);
#pragma omp parallel for schedule(static)
  for (Index v = 0; v < nv; ++v) {
    const Trial& t = found.trials[v];
    // phi_i = w_i p^(X_i)^T A^-1 p^(S) = w_i c . p^(X_i) with A^ c = e1 (A^ symmetric). The guard above
    // bounds cond(A^) <= cond_limit, so this SPD solve loses at most ~3 digits in double.
    const Vec4 c = t.A.llt().solve(Vec4::UnitX());
    for (std::size_t a = 0; a < t.nodes.size(); ++a) {
      const Index e = row_start_[v] + static_cast<Index>(a);
      col_[e] = t.nodes[a];
      val_[e] = t.w[a] * c.dot(basis(rest_nodes_[t.nodes[a]], rest_surface_[v], radius_[v]));
      val_f32_[e] = static_cast<float>(val_[e]);
    }
    cond_[v] = t.cond;
  }
  build_transpose();
  fill_report(r0, found.growths);
}

// The support statistics of report() and the log lines that show them.
void MlsMap::fill_report(double r0, const std::vector<int>& growths) {
  const Index nv = num_vertices();
  report_.base_radius_m = r0;
  report_.max_radius_m = nv > 0 ? *std::max_element(radius_.begin(), radius_.end()) : r0;
  report_.max_cond = nv > 0 ? *std::max_element(cond_.begin(), cond_.end()) : 0.0;
  report_.mean_support = nv > 0 ? static_cast<double>(col_.size()) / nv : 0.0;
  report_.min_support = nv > 0 ? std::numeric_limits<Index>::max() : 0;
  for (Index v = 0; v < nv; ++v) {
    const Index n = row_start_[v + 1] - row_start_[v];
    report_.min_support = std::min(report_.min_support, n);
    report_.max_support = std::max(report_.max_support, n);
    if (growths[v] > 0) ++report_.grown_vertices;
  }
  spdlog::debug("MLS map: {} vertices, {} nodes, support {:.1f} mean [{}, {}], max cond {:.3g}, r0 {:.4g} m",
                nv, num_nodes(), report_.mean_support, report_.min_support, report_.max_support,
                report_.max_cond, r0);
  if (report_.grown_vertices > 0)
    spdlog::info("MLS map: support radius grown for {} of {} surface vertices (|S| / conditioning guard)",
                 report_.grown_vertices, nv);
}

void MlsMap::build_transpose() {
  const Index n = num_nodes();
  t_row_start_.assign(static_cast<std::size_t>(n) + 1, 0);
  for (Index j : col_) ++t_row_start_[j + 1];
  std::partial_sum(t_row_start_.begin(), t_row_start_.end(), t_row_start_.begin());
  t_col_.resize(col_.size());
  t_val_.resize(col_.size());
  std::vector<Index> fill(t_row_start_.begin(), t_row_start_.end() - 1);
  for (Index v = 0; v < num_vertices(); ++v)
    for (Index e = row_start_[v]; e < row_start_[v + 1]; ++e) {
      const Index slot = fill[col_[e]]++;
      t_col_[slot] = v;
      t_val_[slot] = val_[e];
    }
}

void MlsMap::check_node_count(std::size_t given, const char* what) const {
  if (given != rest_nodes_.size())
    throw InputError(fmt::format("MLS map: {} node {} given, {} expected", given, what, num_nodes()));
}

// Row v of the sparse product: sum_e phi_e term(e, node), handed to store(v, sum). Parallel over rows.
template <class Term, class Store>
void MlsMap::for_each_row(Term&& term, Store&& store) const {
  const Index nv = num_vertices();
#pragma omp parallel for schedule(static) if (nv > kParallelRows)
  for (Index v = 0; v < nv; ++v) {
    Vec3 u = Vec3::Zero();
    for (Index e = row_start_[v]; e < row_start_[v + 1]; ++e) u += term(e, col_[e]);
    store(v, u);
  }
}

void MlsMap::map_positions(const Vec3Array& x_nodes_m, Vec3Array& x_surface_m) const {
  check_node_count(x_nodes_m.size(), "positions");
  x_surface_m.resize(rest_surface_.size());
  for_each_row([&](Index e, Index i) -> Vec3 { return val_[e] * (x_nodes_m[i] - rest_nodes_[i]); },
               [&](Index v, const Vec3& u) { x_surface_m[v] = rest_surface_[v] + u; });
}

void MlsMap::map_displacements(const Vec3Array& u_nodes_m, Vec3Array& u_surface_m) const {
  check_node_count(u_nodes_m.size(), "displacements");
  u_surface_m.resize(rest_surface_.size());
  for_each_row([&](Index e, Index i) -> Vec3 { return val_[e] * u_nodes_m[i]; },
               [&](Index v, const Vec3& u) { u_surface_m[v] = u; });
}

void MlsMap::map_displacements_f32(const std::vector<Eigen::Vector3f>& u_nodes_m,
                                   std::vector<Eigen::Vector3f>& x_surface_m) const {
  check_node_count(u_nodes_m.size(), "displacements");
  x_surface_m.resize(rest_surface_.size());
  // float32 shape functions and data, summed in double (the product is bandwidth-bound, the sum is free).
  for_each_row(
      [&](Index e, Index i) -> Vec3 {
        return static_cast<double>(val_f32_[e]) * u_nodes_m[i].cast<double>();
      },
      [&](Index v, const Vec3& u) { x_surface_m[v] = (rest_surface_[v] + u).cast<float>(); });
}

void MlsMap::map_forces_to_nodes(const Vec3Array& f_surface_n, Vec3Array& f_nodes_n) const {
  if (f_surface_n.size() != rest_surface_.size())
    throw InputError(
        fmt::format("MLS map: {} surface forces given, {} expected", f_surface_n.size(), num_vertices()));
  const Index n = num_nodes();
  f_nodes_n.resize(rest_nodes_.size());
#pragma omp parallel for schedule(static) if (n > kParallelRows)
  for (Index i = 0; i < n; ++i) {
    Vec3 f = Vec3::Zero();
    for (Index e = t_row_start_[i]; e < t_row_start_[i + 1]; ++e) f += t_val_[e] * f_surface_n[t_col_[e]];
    f_nodes_n[i] = f;
  }
}

}  // namespace vascsim
