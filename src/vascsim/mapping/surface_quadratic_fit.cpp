#include "vascsim/mapping/surface_quadratic_fit.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "vascsim/core/error.hpp"
#include "vascsim/core/spatial_grid.hpp"

namespace vascsim {

namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

struct Candidate {
  std::size_t k;  // entry in SurfaceNodes
  double a, b;    // tangent coordinates over the radius
  double w;       // kernel weight
};

// The fit at one point with radius r: the row, or false when it is not conditioned.
bool fit_at(const SurfaceNodes& nodes, const SpatialGrid& grid, const Vec3& p, const Vec3& n,
            const SurfaceCorners& corners, double r, const SurfaceQuadraticFitOptions& opt,
            SurfaceFitRow& row) {
  const Vec3 t1 = n.unitOrthogonal(),
             t2 = n.cross(t1);  // any tangent frame: the fit's monomials span the same
  std::vector<Candidate> cands;
  grid.for_each_within(p, r, [&](Index j, double dist) {
    const auto k = static_cast<std::size_t>(j);
    if (nodes.normal[k].dot(n) < opt.min_normal_dot) return;
    const Vec3 d = nodes.position_m[k] - p;
    const double q = dist / r;
    const double s = 1.0 - q * q;
    cands.push_back({k, d.dot(t1) / r, d.dot(t2) / r, s * s * s});
  });
  if (cands.size() < 6) return false;
  Mat6 M = Mat6::Zero();
  for (const Candidate& c : cands) {
    Vec6 b;
    b << 1.0, c.a, c.b, c.a * c.a, c.a * c.b, c.b * c.b;
    M.noalias() += c.w * b * b.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Mat6> eig(M, Eigen::EigenvaluesOnly);
  const double hi = eig.eigenvalues().maxCoeff(), lo = eig.eigenvalues().minCoeff();
  if (!(hi > 0.0) || !(lo >= opt.min_eigen_ratio * hi)) return false;
  // The interpolant's error for the fitted quadratic: -sum_k beta_k (its quadratic part at corner k), so
  // phi_i = -w_i b(a_i)^T M^{-1} g with g = (0, 0, 0, sum_k beta_k (a_k^2, a_k b_k, b_k^2)).
  Vec6 g = Vec6::Zero();
  for (int k = 0; k < 3; ++k) {
    const Vec3 d = corners.position_m[static_cast<std::size_t>(k)] - p;
    const double a = d.dot(t1) / r, b = d.dot(t2) / r, beta = corners.weight[k];
    g.tail<3>() += beta * Vec3(a * a, a * b, b * b);
  }
  const Vec6 c = M.ldlt().solve(g);
  row.node.clear();
  row.phi.clear();
  for (const Candidate& cd : cands) {
    Vec6 b;
    b << 1.0, cd.a, cd.b, cd.a * cd.a, cd.a * cd.b, cd.b * cd.b;
    const double phi = -cd.w * b.dot(c);
    if (phi == 0.0) continue;
    row.node.push_back(nodes.node[cd.k]);
    row.phi.push_back(phi);
  }
  return true;
}

}  // namespace

std::vector<SurfaceFitRow> surface_curvature_rows(const SurfaceNodes& nodes, const Vec3Array& points_m,
                                                  const Vec3Array& normals,
                                                  const std::vector<SurfaceCorners>& corners,
                                                  const SurfaceQuadraticFitOptions& opt) {
  if (nodes.node.size() != nodes.position_m.size() || nodes.node.size() != nodes.normal.size())
    throw InputError(
        "surface quadratic fit: the surface nodes' indices, positions and normals differ in number");
  if (points_m.size() != normals.size() || points_m.size() != corners.size())
    throw InputError("surface quadratic fit: the points' positions, normals and corners differ in number");
  if (!(opt.radius_factor > 0.0 && opt.growth_factor > 1.0 && opt.max_growths >= 0 &&
        opt.min_eigen_ratio > 0.0))
    throw InputError(
        "surface quadratic fit: radius factor > 0, growth factor > 1, growths >= 0 and eigen ratio > 0");
  std::vector<SurfaceFitRow> rows(points_m.size());
  if (nodes.node.empty() || points_m.empty()) return rows;
  std::vector<double> edge_m(points_m.size(), 0.0);
  double mean_edge = 0.0;
  for (std::size_t u = 0; u < points_m.size(); ++u) {
    const auto& x = corners[u].position_m;
    for (int k = 0; k < 3; ++k)
      edge_m[u] = std::max(
          edge_m[u], (x[static_cast<std::size_t>((k + 1) % 3)] - x[static_cast<std::size_t>(k)]).norm());
    if (!(edge_m[u] > 0.0 && std::isfinite(edge_m[u])))
      throw InputError("surface quadratic fit: a point's triangle has no extent");
    mean_edge += edge_m[u] / static_cast<double>(points_m.size());
  }
  const SpatialGrid grid(nodes.position_m, opt.radius_factor * mean_edge);
#pragma omp parallel for schedule(dynamic, 256)
  for (std::ptrdiff_t v = 0; v < static_cast<std::ptrdiff_t>(points_m.size()); ++v) {
    const auto u = static_cast<std::size_t>(v);
    double r = opt.radius_factor * edge_m[u];
    for (int g = 0; g <= opt.max_growths; ++g, r *= opt.growth_factor)
      if (fit_at(nodes, grid, points_m[u], normals[u], corners[u], r, opt, rows[u])) break;
  }
  return rows;
}

}  // namespace vascsim
