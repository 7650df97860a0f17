#include "vascsim/model/single_precision_hessian.hpp"

#include <stdexcept>

#include "vascsim/core/parallel.hpp"
#include "vascsim/core/tensor_algebra.hpp"
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
  Fc_.resize(static_cast<std::size_t>(n));
  P_.resize(static_cast<std::size_t>(n));
  u_.resize(static_cast<std::size_t>(n));
  Ft_.resize(static_cast<std::size_t>(n));
  S_.resize(static_cast<std::size_t>(n));
  S_plus_.resize(static_cast<std::size_t>(n));
  Q_.resize(static_cast<std::size_t>(n));
  v_.resize(static_cast<std::size_t>(n));
}

void SinglePrecisionHessian::linearize(const Vec3Array& x) {
  if (same_state(x, x_)) return;
  x_ = x;
  const Discretization& disc = energy_.discretization();
  const Vec3Array& X = disc.rest_positions();
  const Index n = disc.num_nodes();
  const Mat3 I = Mat3::Identity();
  const double lambda = energy_.strain_lambda(), mu = energy_.shear_modulus();
#pragma omp parallel for schedule(static) if (n >= kParallelMinNodes)
  for (Index i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const Mat3 F = disc.deformation_gradient(i, x);
    const Mat3 E = 0.5 * (F.transpose() * F - I);
    const Mat3 S = lambda * E.trace() * I + 2.0 * mu * E;
    Fc_[k] << F.cast<float>(), Eigen::RowVector3f::Zero();
    Ft_[k] << F.transpose().cast<float>(), Eigen::RowVector3f::Zero();
    S_[k] = S.cast<float>();
    S_plus_[k] = positive_part(S).cast<float>();
    // (The stress in double, rounded once: its rounding is then relative to the stress, not to F ~ I.)
    P_[k] << (disc.volumes()[k] * F * S).cast<float>(), Eigen::RowVector3f::Zero();
    const Vec3 u = x[k] - X[k];
    u_[k] =
        Eigen::Vector4f(static_cast<float>(u.x()), static_cast<float>(u.y()), static_cast<float>(u.z()), 0.f);
  }
}

Eigen::Vector4f SinglePrecisionHessian::gather(Index k, const std::vector<Mat43f>& Q,
                                               const std::vector<Eigen::Vector4f>* v) const {
  const auto kk = static_cast<std::size_t>(k);
  const Eigen::Vector3f& dk = self_d_[kk];
  Eigen::Vector4f f = Q[kk].col(0) * dk.x() + Q[kk].col(1) * dk.y() + Q[kk].col(2) * dk.z();
  for (Index e = trow_start_[kk], end = trow_start_[kk + 1]; e < end; ++e) {
    const Pair& p = transposed_[static_cast<std::size_t>(e)];
    const Mat43f& Qi = Q[static_cast<std::size_t>(p.node)];
    f += Qi.col(0) * p.d[0] + Qi.col(1) * p.d[1] + Qi.col(2) * p.d[2];
  }
  if (v) {
    const Eigen::Vector4f vk = (*v)[kk];
    for (Index e = stab_start_[kk], end = stab_start_[kk + 1]; e < end; ++e)
      f += stab_value_[static_cast<std::size_t>(e)] *
           ((*v)[static_cast<std::size_t>(stab_col_[static_cast<std::size_t>(e)])] - vk);
  }
  return f;
}

void SinglePrecisionHessian::forces(Vec3Array& f) const {
  // f = -(sum of V P_i d_ik over the pairs + K u): the product's second pass with the stress in place of its
  // variation (docs/model/08-forces.md).
  const Index n = static_cast<Index>(P_.size());
  f.resize(static_cast<std::size_t>(n));
#pragma omp parallel for schedule(static) if (n >= kParallelMinNodes)
  for (Index k = 0; k < n; ++k) f[static_cast<std::size_t>(k)] = -gather(k, P_, &u_).head<3>().cast<double>();
}

void SinglePrecisionHessian::product(const Vec3Array& v, Vec3Array& out, ProductForm form) const {
  // Vectors are padded to four floats (w = 0) so that each pair's update is a few 4-wide operations
  // instead of a dozen scalar ones: the product is bound by the instructions per pair, not by memory (its
  // arrays stay in cache), docs/performance.md "Real time at hand speed".
  const std::vector<Eigen::Matrix3f>& S = form == ProductForm::Exact ? S_ : S_plus_;
  const bool stabilised = form != ProductForm::Smoothing;
  const Index n = static_cast<Index>(Fc_.size());
  out.resize(static_cast<std::size_t>(n));
#pragma omp parallel if (n >= kParallelMinNodes)
  {
#pragma omp for schedule(static)
    for (Index i = 0; i < n; ++i) {
      const Vec3& vi = v[static_cast<std::size_t>(i)];
      v_[static_cast<std::size_t>(i)] = Eigen::Vector4f(
          static_cast<float>(vi.x()), static_cast<float>(vi.y()), static_cast<float>(vi.z()), 0.f);
    }
    // Pass 1: dF_i = sum_j (v_j - v_i) d_ij^T, and dP_i = V_i (dF S + F dS)
    // (docs/model/10-hessian-product.md).
#pragma omp for schedule(static)
    for (Index i = 0; i < n; ++i) {
      const Eigen::Vector4f vi = v_[static_cast<std::size_t>(i)];
      Eigen::Vector4f c0 = Eigen::Vector4f::Zero(), c1 = c0, c2 = c0;
      for (Index e = row_start_[static_cast<std::size_t>(i)],
                 end = row_start_[static_cast<std::size_t>(i) + 1];
           e < end; ++e) {
        const Pair& p = pairs_[static_cast<std::size_t>(e)];
        const Eigen::Vector4f dv = v_[static_cast<std::size_t>(p.node)] - vi;
        c0 += p.d[0] * dv;
        c1 += p.d[1] * dv;
        c2 += p.d[2] * dv;
      }
      // With F's columns (Fc) and rows (Ft) as 4-wide columns, every 3 x 3 product below is a sum of
      // column-times-scalar terms: G = F^T dF, dE = sym(G), dS = lambda tr(dE) I + 2 mu dE,
      // dP = V (dF S + F dS), column by column.
      const Eigen::Matrix<float, 4, 3>& Fc = Fc_[static_cast<std::size_t>(i)];
      const Eigen::Matrix<float, 4, 3>& Ft = Ft_[static_cast<std::size_t>(i)];
      const Eigen::Vector4f* c[3] = {&c0, &c1, &c2};
      Eigen::Vector4f g[3];
      for (int b = 0; b < 3; ++b)
        g[b] = Ft.col(0) * (*c[b])[0] + Ft.col(1) * (*c[b])[1] + Ft.col(2) * (*c[b])[2];
      Eigen::Matrix3f dS;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) dS(a, b) = mu_ * (g[b][a] + g[a][b]);
      const float tr = lambda_ * (g[0][0] + g[1][1] + g[2][2]);
      dS.diagonal().array() += tr;
      const Eigen::Matrix3f& Si = S[static_cast<std::size_t>(i)];
      const float V = volume_[static_cast<std::size_t>(i)];
      Eigen::Matrix<float, 4, 3>& Qi = Q_[static_cast<std::size_t>(i)];
      for (int b = 0; b < 3; ++b)
        Qi.col(b) = V * (c0 * Si(0, b) + c1 * Si(1, b) + c2 * Si(2, b) + Fc.col(0) * dS(0, b) +
                         Fc.col(1) * dS(1, b) + Fc.col(2) * dS(2, b));
    }
    // Pass 2: out_k = dP_k d_kk + sum_{i: k in N_i} dP_i d_ik, plus the stabiliser sum_c K_kc (v_c - v_k).
#pragma omp for schedule(static)
    for (Index k = 0; k < n; ++k)
      out[static_cast<std::size_t>(k)] = gather(k, Q_, stabilised ? &v_ : nullptr).head<3>().cast<double>();
  }
}

}  // namespace vascsim
