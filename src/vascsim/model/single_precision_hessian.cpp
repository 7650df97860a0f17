#include "vascsim/model/single_precision_hessian.hpp"

#include <Eigen/Eigenvalues>
#include <stdexcept>

#include "vascsim/core/parallel.hpp"
#include "vascsim/model/stabilizer_matrix.hpp"

namespace vascsim {

bool SinglePrecisionHessian::supports(const PointPrimitiveEnergy& energy) {
  const EnergyOptions& o = energy.options();
  return !o.law && o.strain == StrainMeasure::GreenHalf && o.volume_stiffness_pa == 0.0 &&
         energy.discretization().energy_points() == 1;
}

SinglePrecisionHessian::SinglePrecisionHessian(const PointPrimitiveEnergy& energy) : energy_(energy) {
  if (!supports(energy))
    throw std::invalid_argument(
        "SinglePrecisionHessian: only the built-in SVK law with one energy point per node");
  const Discretization& disc = energy.discretization();
  const Index n = disc.num_nodes();
  lambda_ = static_cast<float>(energy.strain_lambda());
  mu_ = static_cast<float>(energy.shear_modulus());
  auto copy = [](const PairTable& T, std::vector<Index>& start, std::vector<Pair>& out) {
    start = T.row_start;
    out.resize(T.col.size());
    for (std::size_t e = 0; e < T.col.size(); ++e)
      out[e] = {
          T.col[e],
          {static_cast<float>(T.d[e].x()), static_cast<float>(T.d[e].y()), static_cast<float>(T.d[e].z())}};
  };
  copy(disc.pairs(), row_start_, pairs_);
  copy(disc.transposed(), trow_start_, transposed_);
  self_d_.resize(static_cast<std::size_t>(n));
  volume_.resize(static_cast<std::size_t>(n));
  for (Index i = 0; i < n; ++i) {
    self_d_[static_cast<std::size_t>(i)] = disc.self_d()[static_cast<std::size_t>(i)].cast<float>();
    volume_[static_cast<std::size_t>(i)] = static_cast<float>(disc.volumes()[static_cast<std::size_t>(i)]);
  }
  Eigen::SparseMatrix<double, Eigen::RowMajor, int> K;
  if (energy.stabilizer_matrix())
    K = energy.stabilizer_matrix()->matrix();
  else if (energy.options().stabilizer_alpha > 0.0)
    K = StabilizerMatrix(disc, energy.stabilizer_coefficients(),
                         energy.options().stabilizer_fit == StabilizerFit::Quadratic)
            .matrix();
  stab_start_.assign(static_cast<std::size_t>(n) + 1, 0);
  if (K.rows() == n) {
    for (Index r = 0; r < n; ++r) {
      for (Eigen::SparseMatrix<double, Eigen::RowMajor, int>::InnerIterator it(K, r); it; ++it)
        if (it.col() != r) {
          stab_col_.push_back(static_cast<Index>(it.col()));
          stab_value_.push_back(static_cast<float>(it.value()));
        }
      stab_start_[static_cast<std::size_t>(r) + 1] = static_cast<Index>(stab_col_.size());
    }
  }
  F_.resize(static_cast<std::size_t>(n));
  S_.resize(static_cast<std::size_t>(n));
  S_plus_.resize(static_cast<std::size_t>(n));
  Q_.resize(static_cast<std::size_t>(n));
  v_.resize(static_cast<std::size_t>(n));
}

void SinglePrecisionHessian::linearize(const Vec3Array& x) {
  const Discretization& disc = energy_.discretization();
  const Index n = disc.num_nodes();
  const Mat3 I = Mat3::Identity();
  const double lambda = energy_.strain_lambda(), mu = energy_.shear_modulus();
#pragma omp parallel for schedule(static) if (n >= kParallelMinNodes)
  for (Index i = 0; i < n; ++i) {
    const Mat3 F = disc.deformation_gradient(i, x);
    const Mat3 E = 0.5 * (F.transpose() * F - I);
    const Mat3 S = lambda * E.trace() * I + 2.0 * mu * E;
    F_[static_cast<std::size_t>(i)] = F.cast<float>();
    S_[static_cast<std::size_t>(i)] = S.cast<float>();
    Eigen::SelfAdjointEigenSolver<Mat3> es;
    es.computeDirect(S);
    S_plus_[static_cast<std::size_t>(i)] =
        es.eigenvalues().minCoeff() >= 0.0
            ? S_[static_cast<std::size_t>(i)]
            : Mat3(es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).asDiagonal() *
                   es.eigenvectors().transpose())
                  .cast<float>();
  }
}

void SinglePrecisionHessian::product(const Vec3Array& v, Vec3Array& out, bool positive) const {
  const std::vector<Eigen::Matrix3f>& S = positive ? S_plus_ : S_;
  const Index n = static_cast<Index>(F_.size());
  const Eigen::Matrix3f I = Eigen::Matrix3f::Identity();
  out.resize(static_cast<std::size_t>(n));
#pragma omp parallel if (n >= kParallelMinNodes)
  {
#pragma omp for schedule(static)
    for (Index i = 0; i < n; ++i)
      v_[static_cast<std::size_t>(i)] = v[static_cast<std::size_t>(i)].cast<float>();
      // Pass 1: dF_i = sum_j (v_j - v_i) d_ij^T, and dP_i = V_i (dF S + F dS)
      // (docs/model/10-hessian-product.md).
#pragma omp for schedule(static)
    for (Index i = 0; i < n; ++i) {
      const Eigen::Vector3f vi = v_[static_cast<std::size_t>(i)];
      Eigen::Vector3f c0 = Eigen::Vector3f::Zero(), c1 = c0, c2 = c0;
      for (Index e = row_start_[static_cast<std::size_t>(i)],
                 end = row_start_[static_cast<std::size_t>(i) + 1];
           e < end; ++e) {
        const Pair& p = pairs_[static_cast<std::size_t>(e)];
        const Eigen::Vector3f dv = v_[static_cast<std::size_t>(p.node)] - vi;
        c0 += p.d[0] * dv;
        c1 += p.d[1] * dv;
        c2 += p.d[2] * dv;
      }
      Eigen::Matrix3f dF;
      dF.col(0) = c0;
      dF.col(1) = c1;
      dF.col(2) = c2;
      const Eigen::Matrix3f& F = F_[static_cast<std::size_t>(i)];
      const Eigen::Matrix3f dE = 0.5f * (dF.transpose() * F + F.transpose() * dF);
      const Eigen::Matrix3f dS = lambda_ * dE.trace() * I + 2.0f * mu_ * dE;
      Q_[static_cast<std::size_t>(i)] =
          volume_[static_cast<std::size_t>(i)] * (dF * S[static_cast<std::size_t>(i)] + F * dS);
    }
    // Pass 2: out_k = dP_k d_kk + sum_{i: k in N_i} dP_i d_ik, plus the stabiliser sum_c K_kc (v_c - v_k).
#pragma omp for schedule(static)
    for (Index k = 0; k < n; ++k) {
      Eigen::Vector3f f = Q_[static_cast<std::size_t>(k)] * self_d_[static_cast<std::size_t>(k)];
      for (Index e = trow_start_[static_cast<std::size_t>(k)],
                 end = trow_start_[static_cast<std::size_t>(k) + 1];
           e < end; ++e) {
        const Pair& p = transposed_[static_cast<std::size_t>(e)];
        f += Q_[static_cast<std::size_t>(p.node)] * Eigen::Map<const Eigen::Vector3f>(p.d);
      }
      const Eigen::Vector3f vk = v_[static_cast<std::size_t>(k)];
      for (Index e = stab_start_[static_cast<std::size_t>(k)],
                 end = stab_start_[static_cast<std::size_t>(k) + 1];
           e < end; ++e)
        f += stab_value_[static_cast<std::size_t>(e)] *
             (v_[static_cast<std::size_t>(stab_col_[static_cast<std::size_t>(e)])] - vk);
      out[static_cast<std::size_t>(k)] = f.cast<double>();
    }
  }
}

}  // namespace vascsim
