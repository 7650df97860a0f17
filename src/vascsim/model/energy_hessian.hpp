#pragma once
// Assembled Hessian d^2U/dx^2 of PointPrimitiveEnergy as a sparse matrix (N/m), for a sparse Cholesky
// preconditioner of the equilibrium solves (backward Euler as minimisation, or quasi-static Newton).
//
// Node i's energy U_i = V_i psi(F_i) + 1/2 k_v V_i (det F_i - 1)^2 depends on the positions of its stencil
// S_i = {i} + N_i through F_i = sum_{k in S_i} x_k d_ik^T (d_ii = -sum_j d_ij), so its Hessian block
// between nodes k, l of S_i is
//     H_kl^(i) [a][b] = sum_{c,d} C_i[(a,c),(b,d)] d_ik[c] d_il[d],   C_i = V_i d^2 psi / dF^2 (9 x 9)
// (the derivative of the force f_k^(i) = -V_i P_i d_ik along x_l). The stabiliser U_hg,i is quadratic in
// x, so its Hessian is constant: c_i R_i^T W_i R_i (x I_3) with r_ij = (R_i x)_j the affine-fit residual.
// The total H_kl sums over every i whose stencil holds both k and l, so H couples every pair of nodes
// that share a neighbourhood (distance up to 2h), about 4-8 times the blocks of the force operator.
//
// Two steps: the symbolic one (constructor) fixes the block pattern, the scatter map of every
// (i, k, l) term to its block, and the constant stabiliser blocks; the numeric one (assemble) refills the
// values at a configuration. The refill gathers each block row independently (no atomics), in parallel
// over block rows with OpenMP.
//
// Options:
// - project_psd: each node's 9x9 tangent C_i (strain and k_v terms) has its negative eigenvalues set to
//   zero, so H is positive semi-definite at any configuration (SVK under compression is indefinite).
// - Compact stencil: keeps only the blocks of stencil pairs (l in N_k or k in N_l) and the diagonal. Each
//   dropped block B = H_kl is lumped onto the diagonal as (B B^T)^(1/2) on node k and (B^T B)^(1/2) on node
//   l. The change [[(B B^T)^(1/2), -B], [-B^T, (B^T B)^(1/2)]] = [U; -V] Sigma [U; -V]^T (B = U Sigma V^T) is
//   positive semi-definite, so H_compact >= H: positive (semi-)definiteness of H carries over (the
//   smallest such correction that does not depend on the vector it acts on).

#include <Eigen/SparseCore>
#include <cstdint>
#include <vector>

#include "vascsim/model/energy_tangents.hpp"

namespace vascsim {

enum class HessianStencil {
  Full,    ///< every block the energy couples (nodes sharing a neighbourhood): the exact Hessian
  Compact  ///< stencil pairs and the diagonal; dropped blocks lumped onto the diagonal (header comment)
};

/// What the compact stencil does with the blocks it drops (B = H_kl, l not a stencil neighbour of k).
enum class CompactLumping {
  Polar,   ///< (B B^T)^(1/2) onto node k's diagonal block: H_compact >= H, so SPD is kept (header comment)
  RowSum,  ///< sym(sum of the dropped B) onto node k's diagonal block: keeps H t ~ 0 for rigid translations t
           ///< (the row sums), but positive definiteness is not guaranteed
  Drop     ///< nothing: the stencil blocks of H only (positive definiteness not guaranteed)
};

struct EnergyHessianOptions {
  HessianStencil stencil = HessianStencil::Full;
  /// Clamp the negative eigenvalues of every node's 9x9 elastic tangent (strain + k_v) to zero.
  bool project_psd = false;
  /// Store only the block lower triangle (block row >= block column; diagonal blocks whole): all a
  /// Cholesky factorisation reads (it reads the scalar lower triangle); about half the memory and the write
  /// traffic. With the full stencil the refill also computes only the stored blocks (about half the
  /// arithmetic; each stored block's sum is the same, term by term, as in the full matrix).
  bool lower_triangle_only = false;
  CompactLumping lumping = CompactLumping::Polar;  ///< Compact only
};

class EnergyHessian {
 public:
  /// Symbolic step. node_slot: per node, its block row/column in the matrix, or -1 for a node whose position
  /// is prescribed (eliminated: its rows and columns are left out); empty: every node, in node order.
  /// The slots of the kept nodes must be 0..n-1, each once. The energy must outlive this object.
  explicit EnergyHessian(const PointPrimitiveEnergy& energy, const EnergyHessianOptions& options = {},
                         std::vector<Index> node_slot = {});

  /// Numeric refill at configuration x (#nodes positions, m). diagonal_shift: per node (by node id), a
  /// stiffness s_i added as s_i I to its diagonal block, N/m (m_i / dt^2 for backward Euler); empty: none.
  void assemble(const Vec3Array& x, const std::vector<double>& diagonal_shift = {});

  /// The matrix (3n x 3n, N/m), column-major with sorted indices and a fixed pattern (explicit zeros kept),
  /// so one symbolic Cholesky analysis serves every refill. Zero until the first assemble.
  const Eigen::SparseMatrix<double>& matrix() const { return H_; }

  const EnergyHessianOptions& options() const { return opt_; }
  const std::vector<Index>& node_slot() const { return slot_; }
  Index num_block_rows() const { return static_cast<Index>(row_node_.size()); }
  /// 3x3 blocks the energy couples, over all block rows (the exact Hessian's pattern).
  std::int64_t num_coupled_blocks() const { return static_cast<std::int64_t>(row_col_.size()); }
  /// 3x3 blocks stored in matrix().
  std::int64_t num_stored_blocks() const { return static_cast<std::int64_t>(H_.nonZeros() / 9); }

 private:
  Index stencil_size(Index i) const;           // 1 + |N_i|
  Index stencil_node(Index i, Index a) const;  // node a of S_i: i, then N_i
  // The symbolic step (the constructor), in order:
  void number_block_rows();
  std::vector<std::vector<Index>> couple_block_rows(std::vector<std::int64_t>& map_count);
  void build_scatter_map(const std::vector<std::vector<Index>>& cols,
                         const std::vector<std::int64_t>& map_count);
  void build_pattern();
  void add_stabilizer_blocks();
  void skip_unstored_blocks();
  void compute_tangents(const Vec3Array& x);

  const PointPrimitiveEnergy& energy_;
  EnergyHessianOptions opt_;
  std::vector<Index> slot_;      // node -> block row (-1 eliminated)
  std::vector<Index> row_node_;  // block row -> node

  // Block row r (node k) couples the sorted block columns row_col_[row_start_[r] .. row_start_[r+1]).
  std::vector<std::int64_t> row_start_;
  std::vector<Index> row_col_;
  std::vector<Index> row_diag_;  // per row: position of the diagonal block in the row
  std::vector<std::int64_t>
      row_dest_;  // per coupled block: index of its (0,0) entry in H_'s values, -1 not stored
  std::vector<Index> col_stride_;  // per block column: 3 x stored blocks (distance between its 3 columns)
  std::vector<char> row_keep_;     // per coupled block: kept by the stencil (Compact); all 1 for Full
  std::vector<double> stab_;       // per coupled block: the constant stabiliser block / I_3, N/m

  // Terms of block row r: the energies i whose stencil holds node k (contrib_start_ range), each with
  // d_ik and, per node l of S_i (in the order i, N_i), the position of block (k, l) in the row (kSkip:
  // l eliminated).
  std::vector<std::int64_t> contrib_start_;
  std::vector<Index> contrib_node_;
  Vec3Array contrib_d_;
  Vec3Array contrib_e_;  // Gauss points: e_ik,c beside d_ik, point_directions per contribution
  std::vector<std::int64_t> contrib_map_;  // offset into map_
  std::vector<std::uint16_t> map_;
  static constexpr std::uint16_t kSkip = 0xFFFF;

  Mat9Array tangent_;  // per node (and point): V d^2 psi/dF^2 (+ k_v), N m (energy_tangents.hpp)
  std::vector<std::vector<Mat3>> scratch_;  // per thread: one block row
  Eigen::SparseMatrix<double> H_;
};

}  // namespace vascsim
