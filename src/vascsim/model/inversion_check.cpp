#include "vascsim/model/inversion_check.hpp"

#include <fmt/format.h>

namespace vascsim {

namespace {

double signed_volume6(const Vec3Array& x, const Tet& t) {
  return (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]).dot(x[t[3]] - x[t[0]]);
}

}  // namespace

std::string InversionReport::describe() const {
  std::string s;
  if (inverted_tets > 0)
    s = fmt::format("{} virtual tetrahedra inverted (the first: {})", inverted_tets, first_tet);
  if (inverted_nodes > 0)
    s += fmt::format("{}{} nodes with det F <= 0 (the first: node {}; smallest det F = {:.3g})",
                     s.empty() ? "" : ", ", inverted_nodes, first_node, min_det_f);
  return s;
}

InversionReport check_inversion(const Problem& problem, const Vec3Array& x) {
  const Discretization& disc = problem.discretization();
  const Vec3Array& X = disc.rest_positions();
  InversionReport r;
  const std::vector<Tet>& tets = disc.tets();
  for (std::size_t t = 0; t < tets.size(); ++t) {
    const double rest = signed_volume6(X, tets[t]);
    if (rest == 0.0) continue;  // a flat rest tetrahedron carries no orientation
    if (!(signed_volume6(x, tets[t]) / rest > 0.0)) {
      if (r.inverted_tets++ == 0) r.first_tet = static_cast<Index>(t);
    }
  }
  for (Index i = 0; i < disc.num_nodes(); ++i) {
    const double det = problem.energy().deformation_gradient(i, x).determinant();
    r.min_det_f = std::min(r.min_det_f, det);
    if (!(det > 0.0)) {
      if (r.inverted_nodes++ == 0) r.first_node = i;
    }
  }
  return r;
}

}  // namespace vascsim
