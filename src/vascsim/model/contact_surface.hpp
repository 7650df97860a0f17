#pragma once
// The wall's surface as the tools meet it in embedded contact (docs/model/22-contact.md section 22.5):
// quadrature points on the rest surface, each with the area it stands for and its shape functions over the
// nodes, so that a point moves with the nodes, x_v = S_v + sum_i phi_vi (x_i - X_i), and a force on it
// reaches the nodes as phi_vi f_v (virtual work). Built once at rest (run/contact_surface_builder.cpp).

#include <cmath>
#include <vector>

#include "vascsim/core/types.hpp"

namespace vascsim {

struct ContactSurface {
  Vec3Array rest_points;         ///< S_v, m
  std::vector<double> area_m2;   ///< per sample, m^2
  std::vector<Index> row_start;  ///< CSR of phi: sample v's nodes are col[row_start[v] .. row_start[v + 1])
  std::vector<Index> col;
  std::vector<double> val;
  std::vector<double> phi_l1;       ///< per sample sum_i |phi_vi|: |x_v - S_v| <= phi_l1 * max_i |x_i - X_i|
  double stiffness_pa_per_m = 0.0;  ///< normal pressure per metre of penetration, Pa/m
  double sample_spacing_m = 0.0;    ///< the spacing the samples were made at, m

  Index num_samples() const { return static_cast<Index>(area_m2.size()); }
  /// Fills phi_l1 from the CSR.
  void finish() {
    phi_l1.assign(area_m2.size(), 0.0);
    for (std::size_t v = 0; v < area_m2.size(); ++v)
      for (Index k = row_start[v]; k < row_start[v + 1]; ++k)
        phi_l1[v] += std::abs(val[static_cast<std::size_t>(k)]);
  }
};

}  // namespace vascsim
