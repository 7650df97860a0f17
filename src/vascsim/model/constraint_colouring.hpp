#pragma once
// Greedy graph colouring of constraints for parallel Gauss-Seidel (docs/model/19-position-based.md;
// docs/performance.md): two constraints conflict when their stencils (the nodes they read and move) share a
// node; constraints of one colour share no node and can be projected concurrently without races. Computed
// once (total Lagrangian).
//
// Stencils in use: virtual tets (4 nodes; ~30-40 colours), tet edges (2), and the meshless strain
// constraint of node i, whose stencil is {i} u N_i (conflicts reach 2h; 60-100 colours,
// docs/model/19-position-based.md).

#include <vector>

#include "vascsim/model/discretization.hpp"

namespace vascsim {

/// Constraints grouped by colour: colour c holds order[start[c] .. start[c+1]) (constraint indices,
/// ascending within a colour so a static parallel schedule touches memory in order).
struct Colouring {
  std::vector<Index> order;
  std::vector<Index> start;  ///< num_colours() + 1 offsets
  int num_colours() const { return start.empty() ? 0 : static_cast<int>(start.size()) - 1; }
  Index colour_size(int c) const { return start[c + 1] - start[c]; }
};

/// Colours constraint s, whose stencil is nodes[stencil_start[s] .. stencil_start[s+1]), so that no two
/// constraints of one colour share a node. Greedy, first fit, constraints visited in index order.
/// Throws std::invalid_argument if a node index is outside [0, num_nodes).
Colouring colour_stencils(const std::vector<Index>& stencil_start, const std::vector<Index>& nodes,
                          Index num_nodes);

/// The meshless strain constraints' stencils {i} u N_i (row i of `pairs`), in the CSR form colour_stencils
/// takes.
void node_stencils(const PairTable& pairs, std::vector<Index>& stencil_start, std::vector<Index>& nodes);

/// Checks the invariant (for tests): every colour's stencils are pairwise node-disjoint and every
/// constraint appears exactly once.
bool is_valid_colouring(const Colouring& colouring, const std::vector<Index>& stencil_start,
                        const std::vector<Index>& nodes, Index num_nodes);

}  // namespace vascsim
