#pragma once
// A prolongation P from a coarse set of nodes to the nodes of a discretisation, the same for each
// displacement component: fine node k moves by sum_J P_kJ u_J. Rows of prescribed nodes are empty (their
// displacement is not an unknown). Used by the coarse level of the wall multigrid (wall_coarse_space.hpp,
// galerkin_hessian.hpp).

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "vascsim/core/types.hpp"

namespace vascsim {

struct NodalProlongation {
  Index coarse_nodes = 0;               ///< coarse nodes (3 unknowns each)
  std::vector<std::int64_t> row_start;  ///< per fine node + 1: its entries [row_start[k], row_start[k+1])
  std::vector<Index> coarse;            ///< coarse node of each entry
  std::vector<double> weight;           ///< P_kJ of each entry (dimensionless)

  Index fine_nodes() const { return row_start.empty() ? 0 : static_cast<Index>(row_start.size() - 1); }
  /// c = P^T f (3 per coarse node, x y z), N for f in N.
  void restrict_to(const Vec3Array& f, Eigen::VectorXd& c) const {
    c.setZero(3 * static_cast<Eigen::Index>(coarse_nodes));
    for (Index k = 0; k < fine_nodes(); ++k)
      for (std::int64_t e = row_start[static_cast<std::size_t>(k)];
           e < row_start[static_cast<std::size_t>(k) + 1]; ++e)
        c.segment<3>(3 * static_cast<Eigen::Index>(coarse[static_cast<std::size_t>(e)])) +=
            weight[static_cast<std::size_t>(e)] * f[static_cast<std::size_t>(k)];
  }
  /// f += P c, m for c in m.
  void prolongate_add(const Eigen::VectorXd& c, Vec3Array& f) const {
    for (Index k = 0; k < fine_nodes(); ++k) {
      Vec3 u = Vec3::Zero();
      for (std::int64_t e = row_start[static_cast<std::size_t>(k)];
           e < row_start[static_cast<std::size_t>(k) + 1]; ++e)
        u += weight[static_cast<std::size_t>(e)] *
             c.segment<3>(3 * static_cast<Eigen::Index>(coarse[static_cast<std::size_t>(e)]));
      f[static_cast<std::size_t>(k)] += u;
    }
  }
};

}  // namespace vascsim
