#pragma once
// The free nodes of a problem (those whose position is not prescribed) and their packing into the flat
// vectors that sparse factorisations work on: slot a of free node i holds its x, y, z at 3a, 3a+1, 3a+2.

#include <Eigen/Core>
#include <vector>

#include "vascsim/model/problem.hpp"

namespace vascsim {

struct FreeDofs {
  std::vector<Index> nodes;  ///< free node ids, in increasing order
  std::vector<Index> slot;   ///< per node: its index in `nodes`, -1 for a prescribed node

  explicit FreeDofs(const Problem& problem) {
    const Index n = problem.discretization().num_nodes();
    slot.assign(static_cast<std::size_t>(n), -1);
    for (Index i = 0; i < n; ++i)
      if (!problem.constrained()[i]) {
        slot[static_cast<std::size_t>(i)] = static_cast<Index>(nodes.size());
        nodes.push_back(i);
      }
  }
  Eigen::Index size() const { return static_cast<Eigen::Index>(nodes.size()) * 3; }

  /// v (per node) -> packed (free nodes only).
  void pack(const Vec3Array& v, Eigen::VectorXd& packed) const {
    packed.resize(size());
    for (std::size_t a = 0; a < nodes.size(); ++a)
      packed.segment<3>(3 * static_cast<Eigen::Index>(a)) = v[nodes[a]];
  }
  /// packed -> v (per node; prescribed nodes left as they are).
  void unpack(const Eigen::VectorXd& packed, Vec3Array& v) const {
    for (std::size_t a = 0; a < nodes.size(); ++a)
      v[nodes[a]] = packed.segment<3>(3 * static_cast<Eigen::Index>(a));
  }
};

}  // namespace vascsim
