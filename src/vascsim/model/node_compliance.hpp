#pragma once
// The compliance of single nodes seen through the preconditioner's factor P: per free node i, the three
// columns Z_i = P^{-1} E_i (E_i: the unit vectors of its x, y, z), from which
//     C_cd = E_c^T Z_d = E_c^T P^{-1} E_d      (3 x 3, the displacement at c per unit force at d)
// builds every contact-space compliance the equilibrium solver and the haptic hand-off need: the contact
// correction's C over the contact nodes, and W = N P^{-1} N^T over the candidate contacts (n_c^T C_cd n_d).
//
// Why per node: the sets change by a node or two from frame to frame (a contact closes, a node comes within
// reach of the tool), and a multi-column back-solve costs about as much as three or four single ones, so the
// contact correction and the candidates used to redo a 20-30-column solve whenever their set changed. Cached
// per node, a frame solves only the nodes it has not seen since the factor was built; a new factor (a new
// version) starts the cache afresh. Both users share one cache, so a node costs one solve for both.

#include <Eigen/Core>
#include <unordered_map>
#include <vector>

#include "vascsim/model/equilibrium_preconditioner.hpp"
#include "vascsim/model/free_dofs.hpp"

namespace vascsim {

class NodeCompliance {
 public:
  /// At most `capacity` nodes are kept; beyond that the least recently used are dropped.
  explicit NodeCompliance(const FreeDofs& free, std::size_t capacity = 96)
      : free_(free), capacity_(capacity) {}
  /// Makes sure every node of `nodes` (free nodes) has its Z_i for `preconditioner`, solving the missing ones
  /// in one multi-column back-solve. False when the preconditioner has no multi-column solves.
  bool prepare(const std::vector<Index>& nodes, const EquilibriumPreconditioner& preconditioner);
  /// Z_i (free dofs x 3): P^{-1} E_i. Only after prepare() with i.
  const Eigen::MatrixX3d& columns(Index node) const { return cache_.at(node).Z; }
  /// C_cd = E_c^T P^{-1} E_d (3 x 3), m/N. Only after prepare() with d.
  Mat3 coupling(Index c, Index d) const {
    return columns(d).middleRows<3>(3 * static_cast<Eigen::Index>(free_.slot[static_cast<std::size_t>(c)]));
  }
  /// The factor version the cache holds.
  long long version() const { return version_; }
  /// Columns solved since construction (a measure of what the cache saves).
  long long columns_solved() const { return solved_; }

 private:
  struct Entry {
    Eigen::MatrixX3d Z;
    long long last_use = 0;
  };
  void evict(std::size_t keep_at_most);
  const FreeDofs& free_;
  std::size_t capacity_;
  std::unordered_map<Index, Entry> cache_;
  long long version_ = -1, clock_ = 0, solved_ = 0;
};

}  // namespace vascsim
