#include "vascsim/model/integration_constraint.hpp"

#include <algorithm>
#include <cmath>

#include "vascsim/geometry/boundary.hpp"

namespace vascsim {

Vec3Array integration_residuals(const Discretization& disc) {
  const Index n = disc.num_nodes();
  const int points = disc.energy_points(), G = disc.point_directions();
  const PairTable& P = disc.pairs();
  Vec3Array c(static_cast<std::size_t>(n), Vec3::Zero());
  for (Index i = 0; i < n; ++i) {
    const std::size_t ii = static_cast<std::size_t>(i);
    const double W = disc.volumes()[ii] / points;
    // The gradient vector a node gets at point q: d plus the point's offsets times the derivatives e.
    auto at_point = [&](int q, const Vec3& d, const Vec3* e) {
      Vec3 g = d;
      for (int k = 0; k < G; ++k) g += disc.point_offset(i, q, k) * e[k];
      return g;
    };
    for (int q = 0; q < points; ++q) {
      c[ii] +=
          W * at_point(q, disc.self_d()[ii], G ? &disc.self_e()[ii * static_cast<std::size_t>(G)] : nullptr);
      for (Index e = P.row_start[i]; e < P.row_start[i + 1]; ++e) {
        const std::size_t ee = static_cast<std::size_t>(e);
        c[static_cast<std::size_t>(P.col[e])] +=
            W * at_point(q, P.d[ee], G ? &P.e[ee * static_cast<std::size_t>(G)] : nullptr);
      }
    }
  }
  return c;
}

IntegrationConstraintReport integration_constraint_report(const Discretization& disc) {
  const Index n = disc.num_nodes();
  const std::vector<Triangle> faces = boundary_faces(disc.tets());
  const std::vector<double> area =
      lumped_boundary_area(disc.rest_positions(), faces, std::vector<char>(static_cast<std::size_t>(n), 1));
  std::vector<char> on_boundary(static_cast<std::size_t>(n), 0);
  for (const Triangle& f : faces)
    for (Index a : f) on_boundary[static_cast<std::size_t>(a)] = 1;
  IntegrationConstraintReport r;
  Index boundary_nodes = 0;
  for (Index i = 0; i < n; ++i)
    if (on_boundary[static_cast<std::size_t>(i)]) {
      r.boundary_area_m2 += area[static_cast<std::size_t>(i)];
      ++boundary_nodes;
    }
  if (boundary_nodes == 0) return r;
  r.boundary_area_m2 /= static_cast<double>(boundary_nodes);
  const Vec3Array c = integration_residuals(disc);
  double sum_sq = 0.0;
  for (Index i = 0; i < n; ++i) {
    if (on_boundary[static_cast<std::size_t>(i)]) continue;
    const double v = c[static_cast<std::size_t>(i)].norm() / r.boundary_area_m2;
    r.interior_max = std::max(r.interior_max, v);
    sum_sq += v * v;
    ++r.interior_nodes;
  }
  if (r.interior_nodes > 0) r.interior_rms = std::sqrt(sum_sq / static_cast<double>(r.interior_nodes));
  return r;
}

}  // namespace vascsim
