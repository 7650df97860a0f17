#include "vascsim/model/stabilizer_matrix.hpp"

#include <algorithm>

#include "vascsim/core/parallel.hpp"

namespace vascsim {

StabilizerMatrix::StabilizerMatrix(const Discretization& disc, const std::vector<double>& c, bool quadratic) {
  const Index n = disc.num_nodes();
  const PairTable& P = disc.pairs();
  K_.resize(n, n);
  // Assembled in chunks of nodes so that the triplets of a large body (about (K+1)^2 per node) never all
  // exist at once; each chunk's sum is added to K.
  constexpr Index kChunk = 2048;
  std::vector<Eigen::Triplet<double, int>> triplets;
  Eigen::MatrixXd S;
  for (Index first = 0; first < n; first += kChunk) {
    triplets.clear();
    for (Index i = first; i < std::min(n, first + kChunk); ++i) {
      const Index K = P.row_size(i);
      const Index e0 = P.row_start[i];
      const Eigen::MatrixXd R = disc.fit_residual_operator(i, quadratic);
      const Eigen::Map<const Eigen::VectorXd> w(P.w.data() + e0, K);
      S.noalias() = c[static_cast<std::size_t>(i)] * R.transpose() * w.asDiagonal() * R;
      auto node = [&](Index a) { return a == 0 ? i : P.col[e0 + a - 1]; };
      for (Index a = 0; a <= K; ++a)
        for (Index b = 0; b <= K; ++b) triplets.emplace_back(node(a), node(b), S(a, b));
    }
    Eigen::SparseMatrix<double, Eigen::RowMajor, int> part(n, n);
    part.setFromTriplets(triplets.begin(), triplets.end());
    K_ += part;
  }
  K_.makeCompressed();
}

// K annihilates constants (every residual vanishes on a translation: R_i 1 = 0), so each row sums to zero and
// (K v)_r = sum_c K_rc (v_c - v_r), v . K v = -1/2 sum_{r,c} K_rc |v_c - v_r|^2. Both are evaluated from the
// differences: a large translation or rotation of the body then leaves rounding of the size of the
// differences (node spacings), not of the displacements.
namespace {
// out += sign * K v; with kEnergy also sum_{r,c} K_rc |v_c - v_r|^2 (a fifth of the forces' time on the
// real-time vein: only where the energy is wanted).
template <bool kEnergy>
double stabilizer_product(const Eigen::SparseMatrix<double, Eigen::RowMajor, int>& K, const Vec3Array& v,
                          Vec3Array& out, double sign) {
  const Index n = static_cast<Index>(K.rows());
  const int* outer = K.outerIndexPtr();
  const int* inner = K.innerIndexPtr();
  const double* value = K.valuePtr();
  double sum = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : sum) if (n >= kParallelMinNodes)
  for (Index r = 0; r < n; ++r) {
    const Vec3 vr = v[static_cast<std::size_t>(r)];
    Vec3 acc = Vec3::Zero();
    for (int p = outer[r]; p < outer[r + 1]; ++p) {
      const Vec3 diff = v[static_cast<std::size_t>(inner[p])] - vr;
      acc += value[p] * diff;
      if constexpr (kEnergy) sum += value[p] * diff.squaredNorm();
    }
    out[static_cast<std::size_t>(r)] += sign * acc;
  }
  return -0.25 * sum;
}
}  // namespace

void StabilizerMatrix::add_product(const Vec3Array& v, Vec3Array& out, double sign) const {
  stabilizer_product<false>(K_, v, out, sign);
}

double StabilizerMatrix::add_product_and_energy(const Vec3Array& v, Vec3Array& out, double sign) const {
  return stabilizer_product<true>(K_, v, out, sign);
}

double StabilizerMatrix::energy(const Vec3Array& u) const {
  const Index n = static_cast<Index>(K_.rows());
  const int* outer = K_.outerIndexPtr();
  const int* inner = K_.innerIndexPtr();
  const double* value = K_.valuePtr();
  double sum = 0.0;  // sum_{r,c} K_rc |u_c - u_r|^2
#pragma omp parallel for schedule(static) reduction(+ : sum) if (n >= kParallelMinNodes)
  for (Index r = 0; r < n; ++r)
    for (int p = outer[r]; p < outer[r + 1]; ++p)
      sum +=
          value[p] * (u[static_cast<std::size_t>(inner[p])] - u[static_cast<std::size_t>(r)]).squaredNorm();
  return -0.25 * sum;
}

}  // namespace vascsim
