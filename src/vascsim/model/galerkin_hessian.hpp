#pragma once
// The Galerkin coarse form of the point-primitive Hessian, A_c = P^T (K + S) P, for a nodal prolongation P
// (nodal_prolongation.hpp): K the elastic Hessian at a configuration (from the per-node tangents C_i,
// energy_tangents.hpp), S its constant part (the zero-energy-mode stabiliser's Hessian and a diagonal shift
// such as M/h^2). Assembled without the fine matrix: node i's energy depends on its stencil S_i through F_i =
// sum_k x_k d_ik^T, so through the coarse unknowns by the coarse gradient vectors
//     g_iJ = sum_{k in S_i} P_kJ d_ik,
// and contributes the blocks A_c[J, L] += sum_{c,d} C_i[(., c), (., d)] g_iJ[c] g_iL[d] - the fine formula
// with d replaced by g. With P the identity this is the assembled fine Hessian
// (tests/model/test_galerkin_hessian.cpp).
//
// Two steps: the constructor fixes every node's coarse stencil, the block pattern and the constant part;
// assemble() refills the numbers from tangents. The matrix is stored as its block lower triangle (diagonal
// blocks whole), all a Cholesky factorisation reads. One energy point per node.

#include <Eigen/SparseCore>
#include <cstdint>
#include <vector>

#include "vascsim/model/energy_tangents.hpp"
#include "vascsim/model/nodal_prolongation.hpp"

namespace vascsim {

class GalerkinHessian {
 public:
  /// diagonal_shift: per node s_k (N/m), added as s_k I to node k's diagonal block before coarsening (m_k/h^2
  /// for backward Euler); empty: none. Throws std::invalid_argument for a discretisation with several energy
  /// points per node or a prolongation of another size.
  GalerkinHessian(const PointPrimitiveEnergy& energy, const NodalProlongation& prolongation,
                  const std::vector<double>& diagonal_shift = {});

  /// A_c from per-node tangents (energy_tangents; projected to PSD for a preconditioner) into `out`: 3 n_c x
  /// 3 n_c, N/m, column-major and sorted with a fixed pattern (one symbolic Cholesky analysis serves every
  /// refill). Const: several threads may assemble at once into their own matrices.
  void assemble(const Mat9Array& tangents, Eigen::SparseMatrix<double>& out) const;
  Index coarse_nodes() const { return nc_; }
  /// Coupled coarse blocks (the lower triangle and the diagonal).
  std::int64_t blocks() const { return static_cast<std::int64_t>(block_base_.size()); }

 private:
  void build_stencils(const NodalProlongation& P);
  void build_pattern();
  void add_constant_part(const NodalProlongation& P, const std::vector<double>& shift);
  Index block_of(Index row, Index col) const;  // stored block (row >= col), -1 if absent

  const PointPrimitiveEnergy& energy_;
  Index nc_ = 0;
  // Node i's coarse stencil: entries [stencil_start_[i], stencil_start_[i+1]) of (coarse node, g_iJ), by
  // coarse node.
  std::vector<std::int64_t> stencil_start_;
  std::vector<Index> stencil_node_;
  Vec3Array stencil_g_;
  // Per node, per stencil pair (a, b) with node(a) >= node(b), in the order assemble() visits them: the
  // block.
  std::vector<std::int64_t> pair_start_;
  std::vector<Index> pair_block_;
  // Per stored block: where its (0, 0) value is and the distance between its columns in the value array.
  std::vector<std::int64_t> block_base_;
  std::vector<Index> block_stride_;
  std::vector<Index> column_start_;  // per coarse node (column of blocks) + 1: its blocks, by row
  std::vector<Index> block_row_;     // per stored block: its block row
  std::vector<double> constant_;     // the constant part, in value order
  Eigen::SparseMatrix<double> A_;    // the pattern, zero-valued
};

}  // namespace vascsim
