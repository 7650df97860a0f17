#include "vascsim/model/energy_hessian.hpp"

#include <omp.h>

#include <fmt/format.h>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <limits>

#include "vascsim/core/error.hpp"
#include "vascsim/core/tensor_algebra.hpp"

namespace vascsim {

namespace {

// Below this many block rows a parallel region costs more than it saves.
constexpr Index kParallelMinRows = 2048;

// Symmetric square root of a symmetric positive semi-definite 3x3 matrix.
Mat3 psd_sqrt(const Mat3& A) {
  Eigen::SelfAdjointEigenSolver<Mat3> es;
  es.computeDirect(A);
  const Vec3 s = es.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  return es.eigenvectors() * s.asDiagonal() * es.eigenvectors().transpose();
}

}  // namespace

// Stencil of node i: i itself, then N_i (the order of PairTable row i).
Index EnergyHessian::stencil_size(Index i) const {
  return 1 + energy_.discretization().pairs().row_size(i);
}
Index EnergyHessian::stencil_node(Index i, Index a) const {
  const PairTable& P = energy_.discretization().pairs();
  return a == 0 ? i : P.col[static_cast<std::size_t>(P.row_start[i] + a - 1)];
}

EnergyHessian::EnergyHessian(const PointPrimitiveEnergy& energy, const EnergyHessianOptions& options,
                             std::vector<Index> node_slot)
    : energy_(energy), opt_(options), slot_(std::move(node_slot)) {
  number_block_rows();
  std::vector<std::int64_t> map_count;
  std::vector<std::vector<Index>> cols = couple_block_rows(map_count);
  build_scatter_map(cols, map_count);
  build_pattern();
  const std::int64_t nblocks = row_start_.back();
  stab_.assign(static_cast<std::size_t>(nblocks), 0.0);
  if (energy.options().stabilizer_alpha > 0.0) add_stabilizer_blocks();
  skip_unstored_blocks();
  tangent_.resize(static_cast<std::size_t>(energy.discretization().num_nodes() *
                                           energy.discretization().energy_points()));
}

// The block row of every kept node (node_slot, or node order), and the node of every block row.
void EnergyHessian::number_block_rows() {
  const Index n = energy_.discretization().num_nodes();
  if (slot_.empty()) {
    slot_.resize(static_cast<std::size_t>(n));
    for (Index i = 0; i < n; ++i) slot_[static_cast<std::size_t>(i)] = i;
  }
  if (slot_.size() != static_cast<std::size_t>(n))
    throw std::invalid_argument(fmt::format("EnergyHessian: {} node slots for {} nodes", slot_.size(), n));
  Index nrows = 0;
  for (Index s : slot_) nrows += s >= 0 ? 1 : 0;
  row_node_.assign(static_cast<std::size_t>(nrows), -1);
  for (Index i = 0; i < n; ++i) {
    const Index s = slot_[static_cast<std::size_t>(i)];
    if (s < -1 || s >= nrows || (s >= 0 && row_node_[static_cast<std::size_t>(s)] >= 0))
      throw std::invalid_argument("EnergyHessian: node slots must number the kept nodes 0..n-1, each once");
    if (s >= 0) row_node_[static_cast<std::size_t>(s)] = i;
  }
}

// Pass 1: per block row, the coupled block columns (the union of the stencils that hold the row's node), the
// number of energy terms (contrib_start_) and, in map_count, of scatter-map entries before each row.
std::vector<std::vector<Index>> EnergyHessian::couple_block_rows(std::vector<std::int64_t>& map_count) {
  const Discretization& disc = energy_.discretization();
  const PairTable& T = disc.transposed();
  const Index nrows = num_block_rows();
  row_start_.assign(static_cast<std::size_t>(nrows) + 1, 0);
  contrib_start_.assign(static_cast<std::size_t>(nrows) + 1, 0);
  map_count.assign(static_cast<std::size_t>(nrows) + 1, 0);
  std::vector<std::vector<Index>> cols(static_cast<std::size_t>(nrows));
  std::vector<char> mark(static_cast<std::size_t>(nrows), 0);
  {
    for (Index r = 0; r < nrows; ++r) {
      const Index k = row_node_[static_cast<std::size_t>(r)];
      auto& c = cols[static_cast<std::size_t>(r)];
      auto add_stencil = [&](Index i) {
        for (Index a = 0; a < stencil_size(i); ++a) {
          const Index s = slot_[static_cast<std::size_t>(stencil_node(i, a))];
          if (s >= 0 && !mark[static_cast<std::size_t>(s)]) {
            mark[static_cast<std::size_t>(s)] = 1;
            c.push_back(s);
          }
        }
        map_count[static_cast<std::size_t>(r) + 1] += stencil_size(i);
      };
      add_stencil(k);
      for (Index e = T.row_start[k]; e < T.row_start[k + 1]; ++e) add_stencil(T.col[e]);
      for (Index s : c) mark[static_cast<std::size_t>(s)] = 0;
      std::sort(c.begin(), c.end());
      if (c.size() >= kSkip)
        throw std::invalid_argument(fmt::format(
            "EnergyHessian: block row of node {} couples {} blocks (limit {})", k, c.size(), kSkip - 1));
      row_start_[static_cast<std::size_t>(r) + 1] =
          row_start_[static_cast<std::size_t>(r)] + static_cast<std::int64_t>(c.size());
      contrib_start_[static_cast<std::size_t>(r) + 1] =
          contrib_start_[static_cast<std::size_t>(r)] + 1 + T.row_size(k);
      map_count[static_cast<std::size_t>(r) + 1] += map_count[static_cast<std::size_t>(r)];
    }
  }
  return cols;
}

// Pass 2: the scatter map of every (energy i, stencil node l) term of a block row to its block (parallel over
// rows; each row owns its ranges), and the compact stencil's kept blocks.
void EnergyHessian::build_scatter_map(const std::vector<std::vector<Index>>& cols,
                                      const std::vector<std::int64_t>& map_count) {
  const Discretization& disc = energy_.discretization();
  const PairTable& P = disc.pairs();
  const PairTable& T = disc.transposed();
  const Index nrows = num_block_rows();
  const std::int64_t nblocks = row_start_.back();
  row_col_.resize(static_cast<std::size_t>(nblocks));
  row_diag_.resize(static_cast<std::size_t>(nrows));
  row_keep_.assign(static_cast<std::size_t>(nblocks), opt_.stencil == HessianStencil::Full ? 1 : 0);
  contrib_node_.resize(static_cast<std::size_t>(contrib_start_.back()));
  contrib_d_.resize(static_cast<std::size_t>(contrib_start_.back()));
  const std::size_t G = static_cast<std::size_t>(disc.point_directions());
  contrib_e_.resize(static_cast<std::size_t>(contrib_start_.back()) * G);
  contrib_map_.resize(static_cast<std::size_t>(contrib_start_.back()));
  map_.resize(static_cast<std::size_t>(map_count.back()));

  // pos: slot -> position in the row.
#pragma omp parallel if (nrows >= kParallelMinRows)
  {
    std::vector<std::uint16_t> pos(static_cast<std::size_t>(nrows), kSkip);
#pragma omp for schedule(dynamic, 64)
    for (Index r = 0; r < nrows; ++r) {
      const Index k = row_node_[static_cast<std::size_t>(r)];
      const auto& c = cols[static_cast<std::size_t>(r)];
      const std::int64_t base = row_start_[static_cast<std::size_t>(r)];
      for (std::size_t p = 0; p < c.size(); ++p) {
        row_col_[static_cast<std::size_t>(base) + p] = c[p];
        pos[static_cast<std::size_t>(c[p])] = static_cast<std::uint16_t>(p);
        if (c[p] == r) row_diag_[static_cast<std::size_t>(r)] = static_cast<Index>(p);
      }
      if (opt_.stencil == HessianStencil::Compact) {
        // Kept: the diagonal and the stencil pairs, l in N_k (row k of the pairs) or k in N_l (transposed
        // row).
        row_keep_[static_cast<std::size_t>(base + row_diag_[static_cast<std::size_t>(r)])] = 1;
        for (const PairTable* tab : {&P, &T})
          for (Index e = tab->row_start[k]; e < tab->row_start[k + 1]; ++e) {
            const Index s = slot_[static_cast<std::size_t>(tab->col[e])];
            if (s >= 0) row_keep_[static_cast<std::size_t>(base + pos[static_cast<std::size_t>(s)])] = 1;
          }
      }
      std::int64_t m = map_count[static_cast<std::size_t>(r)];
      std::int64_t t = contrib_start_[static_cast<std::size_t>(r)];
      auto add_term = [&](Index i, const Vec3& d_ik, const Vec3* e_ik) {
        contrib_node_[static_cast<std::size_t>(t)] = i;
        contrib_d_[static_cast<std::size_t>(t)] = d_ik;
        for (std::size_t c = 0; c < G; ++c) contrib_e_[static_cast<std::size_t>(t) * G + c] = e_ik[c];
        contrib_map_[static_cast<std::size_t>(t)] = m;
        ++t;
        for (Index a = 0; a < stencil_size(i); ++a) {
          const Index s = slot_[static_cast<std::size_t>(stencil_node(i, a))];
          map_[static_cast<std::size_t>(m++)] = s >= 0 ? pos[static_cast<std::size_t>(s)] : kSkip;
        }
      };
      add_term(k, disc.self_d()[static_cast<std::size_t>(k)],
               G ? &disc.self_e()[static_cast<std::size_t>(k) * G] : nullptr);
      for (Index e = T.row_start[k]; e < T.row_start[k + 1]; ++e)
        add_term(T.col[e], T.d[e], G ? &T.e[static_cast<std::size_t>(e) * G] : nullptr);
      for (Index s : c) pos[static_cast<std::size_t>(s)] = kSkip;
    }
  }
}

// The stored pattern of H_ (CSC, 3x3 blocks, a fixed pattern with explicit zeros).
void EnergyHessian::build_pattern() {
  const Index nrows = num_block_rows();
  const std::int64_t nblocks = row_start_.back();
  // The stored pattern: block column r holds the kept blocks of block row r (the pattern is symmetric),
  // from the diagonal down only if lower_triangle_only. H is symmetric, so block column r is block row r
  // transposed: entry (3 l + a, 3 r + b) = H_rl(b, a).
  row_dest_.assign(static_cast<std::size_t>(nblocks), -1);
  col_stride_.resize(static_cast<std::size_t>(nrows));
  std::vector<std::int64_t> col_base(static_cast<std::size_t>(nrows) + 1, 0);
  for (Index r = 0; r < nrows; ++r) {
    Index stored = 0;
    for (std::int64_t b = row_start_[static_cast<std::size_t>(r)];
         b < row_start_[static_cast<std::size_t>(r) + 1]; ++b)
      if (row_keep_[static_cast<std::size_t>(b)] &&
          (!opt_.lower_triangle_only || row_col_[static_cast<std::size_t>(b)] >= r))
        row_dest_[static_cast<std::size_t>(b)] = col_base[static_cast<std::size_t>(r)] + 3 * stored++;
    col_stride_[static_cast<std::size_t>(r)] = 3 * stored;
    col_base[static_cast<std::size_t>(r) + 1] = col_base[static_cast<std::size_t>(r)] + 9 * stored;
  }
  if (col_base.back() > std::numeric_limits<int>::max())
    throw std::invalid_argument(
        fmt::format("EnergyHessian: {} nonzeros exceed the 32-bit index range", col_base.back()));
  const Eigen::Index dim = 3 * static_cast<Eigen::Index>(nrows);
  H_.resize(dim, dim);
  H_.resizeNonZeros(static_cast<Eigen::Index>(col_base.back()));
  int* outer = H_.outerIndexPtr();
  int* inner = H_.innerIndexPtr();
  for (Index r = 0; r < nrows; ++r) {
    const std::int64_t base = col_base[static_cast<std::size_t>(r)];
    const Index stride = col_stride_[static_cast<std::size_t>(r)];
    for (int b = 0; b < 3; ++b) outer[3 * r + b] = static_cast<int>(base + b * stride);
    for (std::int64_t q = row_start_[static_cast<std::size_t>(r)];
         q < row_start_[static_cast<std::size_t>(r) + 1]; ++q) {
      const std::int64_t dest = row_dest_[static_cast<std::size_t>(q)];
      if (dest < 0) continue;
      for (int b = 0; b < 3; ++b)
        for (int a = 0; a < 3; ++a)
          inner[dest + b * stride + a] = 3 * row_col_[static_cast<std::size_t>(q)] + a;
    }
  }
  outer[dim] = static_cast<int>(col_base.back());
  std::fill(H_.valuePtr(), H_.valuePtr() + H_.nonZeros(), 0.0);
}

void EnergyHessian::add_stabilizer_blocks() {
  // docs/model/09-volume-term-and-stabiliser.md section 9.2: U_hg,i = c_i/2 sum_j w_ij |r_ij|^2 with r_ij the
  // residual of node i's fit (affine or quadratic). Over the stencil (i, N_i) the residuals are r = R x
  // (Discretization::fit_residual_operator), so the Hessian is c_i R^T W R (times I_3): constant.
  const Discretization& disc = energy_.discretization();
  const PairTable& P = disc.pairs();
  const Index n = disc.num_nodes();
  const auto& c = energy_.stabilizer_coefficients();
  const bool quadratic_residual = energy_.options().stabilizer_fit == StabilizerFit::Quadratic;
  // Where term (row of stencil node a, energy i) sits: scan the rows once, indexed by (i, a).
  std::vector<std::int64_t> stencil_start(static_cast<std::size_t>(n) + 1, 0);
  for (Index i = 0; i < n; ++i)
    stencil_start[static_cast<std::size_t>(i) + 1] =
        stencil_start[static_cast<std::size_t>(i)] + 1 + P.row_size(i);
  std::vector<std::int64_t> term_of(static_cast<std::size_t>(stencil_start.back()), -1);
  for (Index r = 0; r < num_block_rows(); ++r) {
    const Index k = row_node_[static_cast<std::size_t>(r)];
    for (std::int64_t t = contrib_start_[static_cast<std::size_t>(r)];
         t < contrib_start_[static_cast<std::size_t>(r) + 1]; ++t) {
      const Index i = contrib_node_[static_cast<std::size_t>(t)];
      Index a = 0;
      if (k != i)
        a = 1 + static_cast<Index>(
                    std::lower_bound(P.col.begin() + P.row_start[i], P.col.begin() + P.row_start[i + 1], k) -
                    (P.col.begin() + P.row_start[i]));
      term_of[static_cast<std::size_t>(stencil_start[static_cast<std::size_t>(i)] + a)] = t;
    }
  }
  Eigen::MatrixXd S;
  for (Index i = 0; i < n; ++i) {
    const Index K = P.row_size(i);
    const Index e0 = P.row_start[i];
    const Eigen::MatrixXd R = disc.fit_residual_operator(i, quadratic_residual);
    const Eigen::Map<const Eigen::VectorXd> w(P.w.data() + e0, K);
    S.noalias() = c[static_cast<std::size_t>(i)] * R.transpose() * w.asDiagonal() * R;
    for (Index a = 0; a <= K; ++a) {
      const std::int64_t t =
          term_of[static_cast<std::size_t>(stencil_start[static_cast<std::size_t>(i)] + a)];
      if (t < 0) continue;  // node a of the stencil is eliminated
      const Index r = slot_[static_cast<std::size_t>(a == 0 ? i : P.col[e0 + a - 1])];
      const std::uint16_t* m = map_.data() + contrib_map_[static_cast<std::size_t>(t)];
      for (Index b = 0; b <= K; ++b)
        if (m[b] != kSkip)
          stab_[static_cast<std::size_t>(row_start_[static_cast<std::size_t>(r)] + m[b])] += S(a, b);
    }
  }
}

// With the lower triangle only and the full stencil, a block that is not stored is never read (the compact
// stencil lumps its dropped blocks, so it needs them all): its scatter-map entries become kSkip, and the
// refill computes about half the blocks. Runs after add_stabilizer_blocks, which fills every coupled block
// through the map.
void EnergyHessian::skip_unstored_blocks() {
  if (!opt_.lower_triangle_only || opt_.stencil != HessianStencil::Full) return;
  const Index nrows = num_block_rows();
#pragma omp parallel for schedule(dynamic, 64) if (nrows >= kParallelMinRows)
  for (Index r = 0; r < nrows; ++r) {
    const std::int64_t b0 = row_start_[static_cast<std::size_t>(r)];
    for (std::int64_t t = contrib_start_[static_cast<std::size_t>(r)];
         t < contrib_start_[static_cast<std::size_t>(r) + 1]; ++t) {
      const Index i = contrib_node_[static_cast<std::size_t>(t)];
      std::uint16_t* m = map_.data() + contrib_map_[static_cast<std::size_t>(t)];
      for (Index a = 0; a < stencil_size(i); ++a)
        if (m[a] != kSkip && row_dest_[static_cast<std::size_t>(b0 + m[a])] < 0) m[a] = kSkip;
    }
  }
}

void EnergyHessian::compute_tangents(const Vec3Array& x) {
  energy_tangents(energy_, x, opt_.project_psd ? TangentProjection::Spectral : TangentProjection::None,
                  tangent_);
}

void EnergyHessian::assemble(const Vec3Array& x, const std::vector<double>& diagonal_shift) {
  const Discretization& disc = energy_.discretization();
  const PairTable& P = disc.pairs();
  if (x.size() != static_cast<std::size_t>(disc.num_nodes()))
    throw std::invalid_argument(
        fmt::format("EnergyHessian::assemble: {} positions for {} nodes", x.size(), disc.num_nodes()));
  if (!diagonal_shift.empty() && diagonal_shift.size() != x.size())
    throw std::invalid_argument("EnergyHessian::assemble: diagonal_shift needs one value per node");
  compute_tangents(x);
  const int points = disc.energy_points();
  const std::size_t G = static_cast<std::size_t>(disc.point_directions());
  const Index nrows = num_block_rows();
  const bool compact = opt_.stencil == HessianStencil::Compact;
  double* values = H_.valuePtr();
  const int threads = nrows >= kParallelMinRows ? omp_get_max_threads() : 1;
  if (static_cast<int>(scratch_.size()) < threads) scratch_.resize(static_cast<std::size_t>(threads));

#pragma omp parallel num_threads(threads)
  {
    std::vector<Mat3>& row = scratch_[static_cast<std::size_t>(omp_get_thread_num())];
#pragma omp for schedule(dynamic, 64)
    for (Index r = 0; r < nrows; ++r) {
      const std::int64_t b0 = row_start_[static_cast<std::size_t>(r)];
      const std::size_t len = static_cast<std::size_t>(row_start_[static_cast<std::size_t>(r) + 1] - b0);
      row.resize(std::max(row.size(), len));
      for (std::size_t p = 0; p < len; ++p)
        row[p] = stab_[static_cast<std::size_t>(b0) + p] * Mat3::Identity();
      // Gather: every energy i whose stencil holds this row's node k adds, for each l of its stencil,
      // H_kl^(i) = sum_d d_il[d] U_d with U = sum_c d_ik[c] C_i[(., c), (., .)] (3 x 9).
      // With Gauss points each point q of energy i adds its own term, with the gradient vectors
      // d + sum_c o_qc e_c of that point.
      for (std::int64_t t = contrib_start_[static_cast<std::size_t>(r)];
           t < contrib_start_[static_cast<std::size_t>(r) + 1]; ++t) {
        const Index i = contrib_node_[static_cast<std::size_t>(t)];
        const std::uint16_t* m = map_.data() + contrib_map_[static_cast<std::size_t>(t)];
        const Index e0 = P.row_start[i], K = P.row_size(i);
        for (int q = 0; q < points; ++q) {
          const Mat9& C = tangent_[static_cast<std::size_t>(i * points + q)];
          // Point q's gradient vectors: d + sum_c o_qc e_c.
          auto at_point = [&](Vec3 d, const Vec3* e) {
            for (std::size_t c = 0; c < G; ++c) d += disc.point_offset(i, q, static_cast<int>(c)) * e[c];
            return d;
          };
          const Vec3 dk = at_point(contrib_d_[static_cast<std::size_t>(t)],
                                   G ? &contrib_e_[static_cast<std::size_t>(t) * G] : nullptr);
          const Eigen::Matrix<double, 3, 9> U =
              dk[0] * C.middleRows<3>(0) + dk[1] * C.middleRows<3>(3) + dk[2] * C.middleRows<3>(6);
          auto add = [&](std::uint16_t p, const Vec3& dl) {
            row[p] += dl[0] * U.middleCols<3>(0) + dl[1] * U.middleCols<3>(3) + dl[2] * U.middleCols<3>(6);
          };
          // A skipped block (eliminated, or not stored) costs neither its gradient vector nor its product.
          if (points == 1) {
            if (m[0] != kSkip) add(m[0], disc.self_d()[static_cast<std::size_t>(i)]);
            for (Index a = 0; a < K; ++a)
              if (m[1 + a] != kSkip) add(m[1 + a], P.d[static_cast<std::size_t>(e0 + a)]);
          } else {
            if (m[0] != kSkip)
              add(m[0], at_point(disc.self_d()[static_cast<std::size_t>(i)],
                                 &disc.self_e()[static_cast<std::size_t>(i) * G]));
            for (Index a = 0; a < K; ++a)
              if (m[1 + a] != kSkip)
                add(m[1 + a], at_point(P.d[static_cast<std::size_t>(e0 + a)],
                                       &P.e[static_cast<std::size_t>(e0 + a) * G]));
          }
        }
      }
      const std::size_t diag = static_cast<std::size_t>(row_diag_[static_cast<std::size_t>(r)]);
      if (!diagonal_shift.empty())
        row[diag].diagonal().array() +=
            diagonal_shift[static_cast<std::size_t>(row_node_[static_cast<std::size_t>(r)])];
      if (compact && opt_.lumping == CompactLumping::Polar) {
        // Lump every dropped block B = H_kl as (B B^T)^(1/2) on this diagonal; row l adds (B^T B)^(1/2) to
        // its own.
        for (std::size_t p = 0; p < len; ++p)
          if (!row_keep_[static_cast<std::size_t>(b0) + p])
            row[diag] += psd_sqrt(row[p] * row[p].transpose());
      } else if (compact && opt_.lumping == CompactLumping::RowSum) {
        Mat3 dropped = Mat3::Zero();
        for (std::size_t p = 0; p < len; ++p)
          if (!row_keep_[static_cast<std::size_t>(b0) + p]) dropped += row[p];
        row[diag] += 0.5 * (dropped + dropped.transpose());
      }
      // Write out, transposed into block column r (see the constructor).
      const Index stride = col_stride_[static_cast<std::size_t>(r)];
      for (std::size_t p = 0; p < len; ++p) {
        const std::int64_t dest = row_dest_[static_cast<std::size_t>(b0) + p];
        if (dest < 0) continue;
        for (int b = 0; b < 3; ++b)
          for (int a = 0; a < 3; ++a) values[dest + b * stride + a] = row[p](b, a);
      }
    }
  }
}

}  // namespace vascsim
