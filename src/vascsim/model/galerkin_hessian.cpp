#include "vascsim/model/galerkin_hessian.hpp"

#include <algorithm>
#include <stdexcept>

#include "vascsim/model/stabilizer_matrix.hpp"

namespace vascsim {

GalerkinHessian::GalerkinHessian(const PointPrimitiveEnergy& energy, const NodalProlongation& prolongation,
                                 const std::vector<double>& diagonal_shift)
    : energy_(energy), nc_(prolongation.coarse_nodes) {
  const Discretization& disc = energy.discretization();
  if (disc.energy_points() != 1)
    throw std::invalid_argument("GalerkinHessian: one energy point per node only");
  if (prolongation.fine_nodes() != disc.num_nodes())
    throw std::invalid_argument(
        "GalerkinHessian: the prolongation's rows are not the discretisation's nodes");
  if (!diagonal_shift.empty() && diagonal_shift.size() != static_cast<std::size_t>(disc.num_nodes()))
    throw std::invalid_argument("GalerkinHessian: diagonal_shift needs one value per node");
  build_stencils(prolongation);
  build_pattern();
  add_constant_part(prolongation, diagonal_shift);
}

void GalerkinHessian::build_stencils(const NodalProlongation& P) {
  const Discretization& disc = energy_.discretization();
  const PairTable& T = disc.pairs();
  const Index n = disc.num_nodes();
  stencil_start_.assign(static_cast<std::size_t>(n) + 1, 0);
  std::vector<std::pair<Index, Vec3>> g;
  auto add = [&](Index k, const Vec3& d) {
    for (std::int64_t e = P.row_start[static_cast<std::size_t>(k)];
         e < P.row_start[static_cast<std::size_t>(k) + 1]; ++e)
      g.push_back({P.coarse[static_cast<std::size_t>(e)], P.weight[static_cast<std::size_t>(e)] * d});
  };
  for (Index i = 0; i < n; ++i) {
    g.clear();
    add(i, disc.self_d()[static_cast<std::size_t>(i)]);
    for (Index e = T.row_start[i]; e < T.row_start[i + 1]; ++e)
      add(T.col[static_cast<std::size_t>(e)], T.d[static_cast<std::size_t>(e)]);
    std::sort(g.begin(), g.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (std::size_t a = 0; a < g.size();) {  // merge the shares of one coarse node
      Vec3 sum = Vec3::Zero();
      const Index J = g[a].first;
      for (; a < g.size() && g[a].first == J; ++a) sum += g[a].second;
      stencil_node_.push_back(J);
      stencil_g_.push_back(sum);
    }
    stencil_start_[static_cast<std::size_t>(i) + 1] = static_cast<std::int64_t>(stencil_node_.size());
  }
}

Index GalerkinHessian::block_of(Index row, Index col) const {
  const auto first = block_row_.begin() + column_start_[static_cast<std::size_t>(col)];
  const auto last = block_row_.begin() + column_start_[static_cast<std::size_t>(col) + 1];
  const auto it = std::lower_bound(first, last, row);
  return it != last && *it == row ? static_cast<Index>(it - block_row_.begin()) : -1;
}

void GalerkinHessian::build_pattern() {
  // Block rows of every column (row >= column), from the stencils' pairs.
  std::vector<std::vector<Index>> rows(static_cast<std::size_t>(nc_));
  const Index n = static_cast<Index>(stencil_start_.size()) - 1;
  for (Index i = 0; i < n; ++i)
    for (std::int64_t a = stencil_start_[static_cast<std::size_t>(i)];
         a < stencil_start_[static_cast<std::size_t>(i) + 1]; ++a)
      for (std::int64_t b = stencil_start_[static_cast<std::size_t>(i)]; b <= a; ++b)
        rows[static_cast<std::size_t>(stencil_node_[static_cast<std::size_t>(b)])].push_back(
            stencil_node_[static_cast<std::size_t>(a)]);
  // Every coarse node has its diagonal block (a coarse node interpolates at least its own fine node).
  for (Index J = 0; J < nc_; ++J) rows[static_cast<std::size_t>(J)].push_back(J);
  column_start_.assign(static_cast<std::size_t>(nc_) + 1, 0);
  for (Index L = 0; L < nc_; ++L) {
    auto& r = rows[static_cast<std::size_t>(L)];
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
    column_start_[static_cast<std::size_t>(L) + 1] =
        column_start_[static_cast<std::size_t>(L)] + static_cast<Index>(r.size());
    block_row_.insert(block_row_.end(), r.begin(), r.end());
  }
  // The scalar CSC layout: column 3L + b holds rows 3J + a of every block (J, L), by J.
  const std::int64_t nnz = 9 * static_cast<std::int64_t>(block_row_.size());
  A_.resize(3 * nc_, 3 * nc_);
  A_.resizeNonZeros(nnz);
  int* outer = A_.outerIndexPtr();
  int* inner = A_.innerIndexPtr();
  block_base_.resize(block_row_.size());
  block_stride_.resize(block_row_.size());
  std::int64_t pos = 0;
  for (Index L = 0; L < nc_; ++L) {
    const Index nb =
        column_start_[static_cast<std::size_t>(L) + 1] - column_start_[static_cast<std::size_t>(L)];
    for (int b = 0; b < 3; ++b) {
      outer[3 * L + b] = static_cast<int>(pos);
      for (Index p = 0; p < nb; ++p) {
        const Index J = block_row_[static_cast<std::size_t>(column_start_[static_cast<std::size_t>(L)] + p)];
        if (b == 0) {
          block_base_[static_cast<std::size_t>(column_start_[static_cast<std::size_t>(L)] + p)] = pos + 3 * p;
          block_stride_[static_cast<std::size_t>(column_start_[static_cast<std::size_t>(L)] + p)] = 3 * nb;
        }
        for (int a = 0; a < 3; ++a) inner[pos + 3 * p + a] = 3 * J + a;
      }
      pos += 3 * nb;
    }
  }
  outer[3 * nc_] = static_cast<int>(pos);
  std::fill(A_.valuePtr(), A_.valuePtr() + nnz, 0.0);
  // Each stencil pair's block, in assemble()'s order.
  pair_start_.assign(static_cast<std::size_t>(n) + 1, 0);
  for (Index i = 0; i < n; ++i) {
    for (std::int64_t a = stencil_start_[static_cast<std::size_t>(i)];
         a < stencil_start_[static_cast<std::size_t>(i) + 1]; ++a)
      for (std::int64_t b = stencil_start_[static_cast<std::size_t>(i)]; b <= a; ++b)
        pair_block_.push_back(
            block_of(stencil_node_[static_cast<std::size_t>(a)], stencil_node_[static_cast<std::size_t>(b)]));
    pair_start_[static_cast<std::size_t>(i) + 1] = static_cast<std::int64_t>(pair_block_.size());
  }
}

void GalerkinHessian::add_constant_part(const NodalProlongation& P, const std::vector<double>& shift) {
  const Discretization& disc = energy_.discretization();
  const Index n = disc.num_nodes();
  using SpMat = Eigen::SparseMatrix<double>;
  std::vector<Eigen::Triplet<double>> t;
  for (Index k = 0; k < n; ++k)
    for (std::int64_t e = P.row_start[static_cast<std::size_t>(k)];
         e < P.row_start[static_cast<std::size_t>(k) + 1]; ++e)
      t.emplace_back(k, P.coarse[static_cast<std::size_t>(e)], P.weight[static_cast<std::size_t>(e)]);
  SpMat Pm(n, nc_);
  Pm.setFromTriplets(t.begin(), t.end());
  // The stabiliser's Hessian K (x I_3): the energy's own matrix, or the one it folds into its stress gather.
  SpMat S(n, n);
  if (const StabilizerMatrix* m = energy_.stabilizer_matrix()) {
    S = m->matrix();
  } else if (energy_.options().stabilizer_alpha > 0.0) {
    S = StabilizerMatrix(disc, energy_.stabilizer_coefficients(),
                         energy_.options().stabilizer_fit == StabilizerFit::Quadratic)
            .matrix();
  }
  if (!shift.empty()) {
    SpMat D(n, n);
    std::vector<Eigen::Triplet<double>> d;
    for (Index k = 0; k < n; ++k) d.emplace_back(k, k, shift[static_cast<std::size_t>(k)]);
    D.setFromTriplets(d.begin(), d.end());
    S += D;
  }
  const SpMat SP = S * Pm;
  const SpMat C = SpMat(Pm.transpose()) * SP;
  constant_.assign(static_cast<std::size_t>(A_.nonZeros()), 0.0);
  for (int L = 0; L < C.outerSize(); ++L)
    for (SpMat::InnerIterator it(C, L); it; ++it) {
      const Index J = static_cast<Index>(it.row());
      if (J < L) continue;
      const Index blk = block_of(J, L);
      if (blk < 0)
        throw std::logic_error("GalerkinHessian: the constant part couples blocks the energy does not");
      const std::int64_t base = block_base_[static_cast<std::size_t>(blk)];
      const Index stride = block_stride_[static_cast<std::size_t>(blk)];
      for (int a = 0; a < 3; ++a) constant_[static_cast<std::size_t>(base + a * stride + a)] += it.value();
    }
}

void GalerkinHessian::assemble(const Mat9Array& tangents, Eigen::SparseMatrix<double>& out) const {
  if (out.rows() != A_.rows() || out.nonZeros() != A_.nonZeros()) out = A_;
  double* values = out.valuePtr();
  std::copy(constant_.begin(), constant_.end(), values);
  const Index n = static_cast<Index>(stencil_start_.size()) - 1;
  for (Index i = 0; i < n; ++i) {
    const Mat9& C = tangents[static_cast<std::size_t>(i)];
    const std::int64_t s0 = stencil_start_[static_cast<std::size_t>(i)],
                       s1 = stencil_start_[static_cast<std::size_t>(i) + 1];
    const Index* blk = pair_block_.data() + pair_start_[static_cast<std::size_t>(i)];
    for (std::int64_t a = s0; a < s1; ++a) {
      const Vec3& ga = stencil_g_[static_cast<std::size_t>(a)];
      const Eigen::Matrix<double, 3, 9> U =
          ga[0] * C.middleRows<3>(0) + ga[1] * C.middleRows<3>(3) + ga[2] * C.middleRows<3>(6);
      for (std::int64_t b = s0; b <= a; ++b, ++blk) {
        const Vec3& gb = stencil_g_[static_cast<std::size_t>(b)];
        const Mat3 B = gb[0] * U.middleCols<3>(0) + gb[1] * U.middleCols<3>(3) + gb[2] * U.middleCols<3>(6);
        double* v = values + block_base_[static_cast<std::size_t>(*blk)];
        const Index stride = block_stride_[static_cast<std::size_t>(*blk)];
        for (int c = 0; c < 3; ++c)
          for (int r = 0; r < 3; ++r) v[c * stride + r] += B(r, c);
      }
    }
  }
}

}  // namespace vascsim
