#include "vascsim/model/point_primitive_energy.hpp"

#include <fmt/format.h>
#include <limits>

#include "vascsim/core/error.hpp"
#include "vascsim/core/parallel.hpp"
#include "vascsim/core/tensor_algebra.hpp"
#include "vascsim/model/stabilizer_matrix.hpp"

namespace vascsim {

// Per thread (a real-time model's background factorisation and its frames may evaluate the same energy at
// once): the per-node buffers of forces() and hessian_product(), kept between calls so that no call
// allocates.
PointPrimitiveEnergy::Workspace& PointPrimitiveEnergy::workspace(Index n) {
  thread_local Workspace ws;
  if (static_cast<Index>(ws.Q.size()) < n) {
    ws.Q.resize(static_cast<std::size_t>(n));
    ws.R.resize(static_cast<std::size_t>(n) * Discretization::kMaxPointDirections);
    ws.own.resize(static_cast<std::size_t>(n));
    ws.u.resize(static_cast<std::size_t>(n));
  }
  return ws;
}

PointPrimitiveEnergy::PointPrimitiveEnergy(const Discretization& disc, const EnergyOptions& options)
    : disc_(disc), opt_(options) {
  const Material& m = disc.material();
  mu_ = m.shear_modulus();
  lambda_ = m.lame_lambda() - opt_.volume_stiffness_pa;
  if (opt_.law) {
    if (opt_.strain != StrainMeasure::GreenHalf)
      throw InputError(
          fmt::format("energy: the literal strain (mueller_no_half) applies to the built-in SVK only, "
                      "not to material law '{}'",
                      opt_.law->name()));
    mu_ = opt_.law->small_strain_shear_modulus();
    lambda_ = opt_.law->small_strain_bulk_modulus() - 2.0 / 3.0 * mu_ - opt_.volume_stiffness_pa;
    if (opt_.law->needs_frame() && opt_.frames.size() != static_cast<std::size_t>(disc.num_nodes()))
      throw InputError(
          fmt::format("energy: material law '{}' needs a wall frame at every node (a vessel geometry)",
                      opt_.law->name()));
  }
  if (opt_.volume_stiffness_pa < 0.0 || lambda_ < 0.0)
    throw InputError(fmt::format("energy: volume stiffness k_v = {} Pa must lie in [0, lambda = {} Pa]",
                                 opt_.volume_stiffness_pa, m.lame_lambda()));
  if (opt_.stabilizer_alpha < 0.0) throw InputError("energy: stabiliser alpha must be >= 0");
  const Index n = disc.num_nodes();
  stab_c_.resize(n);
  for (Index i = 0; i < n; ++i)
    stab_c_[i] = opt_.stabilizer_alpha * mu_ * disc.volumes()[i] / disc.moment_trace()[i];
  // The stabiliser folded into the stress gather (docs/model/09-volume-term-and-stabiliser.md section 9.2):
  // c_i A_i per node, c_i w_ik per transposed pair.
  stab_cA_.resize(n);
  for (Index i = 0; i < n; ++i) stab_cA_[i] = stab_c_[i] * disc.moment_matrices()[i];
  const PairTable& T = disc.transposed();
  stab_cw_.resize(T.col.size());
  for (Index k = 0; k < n; ++k)
    for (Index e = T.row_start[k]; e < T.row_start[k + 1]; ++e) stab_cw_[e] = stab_c_[T.col[e]] * T.w[e];
  if (opt_.stabilizer_alpha > 0.0) {
    if (disc.basis() == GradientBasis::Linear && opt_.stabilizer_fit == StabilizerFit::Basis)
      folded_stab_ = true;
    else
      stab_matrix_ = std::make_shared<const StabilizerMatrix>(
          disc, stab_c_, opt_.stabilizer_fit == StabilizerFit::Quadratic);
  }
}

Mat3 PointPrimitiveEnergy::weighted_stress(Index i, const Mat3& F, double V, EnergyBreakdown* e) const {
  const Mat3 I = Mat3::Identity();
  Mat3 Pt;
  if (opt_.law) {
    const materials::MaterialFrame* frame =
        opt_.frames.empty() ? nullptr : &opt_.frames[static_cast<std::size_t>(i)];
    Pt = V * opt_.law->first_piola(F, frame);
    if (e) e->strain += V * opt_.law->energy_density(F, frame);
  } else if (opt_.strain == StrainMeasure::GreenHalf) {
    const Mat3 E = 0.5 * (F.transpose() * F - I);  // Green-Lagrange strain (Eq. 5 with the 1/2)
    const double trE = E.trace();
    const Mat3 S = lambda_ * trE * I + 2.0 * mu_ * E;  // SVK 2nd Piola-Kirchhoff (Eq. 6, tensor form)
    Pt = V * (F * S);
    if (e) e->strain += V * (mu_ * E.squaredNorm() + 0.5 * lambda_ * trE * trE);
  } else {
    const Mat3 eps = F.transpose() * F - I;  // Eq. 5 as printed (no 1/2)
    const double tr = eps.trace();
    const Mat3 sigma = lambda_ * tr * I + 2.0 * mu_ * eps;
    Pt = 2.0 * V * (F * sigma);  // Mueller's F_e = -2 v J sigma (docs/model/08-forces.md)
    if (e) e->strain += 0.5 * V * (eps.cwiseProduct(sigma)).sum();
  }
  if (opt_.volume_stiffness_pa > 0.0) {
    const double J = F.determinant();
    Pt += opt_.volume_stiffness_pa * V * (J - 1.0) * cofactor(F);
    if (e) e->volume += 0.5 * opt_.volume_stiffness_pa * V * (J - 1.0) * (J - 1.0);
  }
  return Pt;
}

Mat3 PointPrimitiveEnergy::stress(const Mat3& F) const {
  const Mat3 I = Mat3::Identity();
  const double half = opt_.strain == StrainMeasure::GreenHalf ? 0.5 : 1.0;
  const Mat3 E = half * (F.transpose() * F - I);
  return lambda_ * E.trace() * I + 2.0 * mu_ * E;
}

Mat3 PointPrimitiveEnergy::weighted_stress_derivative(Index i, const Mat3& F, const Mat3& S, const Mat3& dF,
                                                      double V) const {
  const Mat3 I = Mat3::Identity();
  // SVK: P = F S, S = lambda tr(E) I + 2 mu E, E = 1/2 (F^T F - I).
  // Literal: Ptilde = 2 V F sigma with sigma of eps = F^T F - I, i.e. "half" = 1 and a factor 2.
  const bool svk = opt_.strain == StrainMeasure::GreenHalf;
  const Mat3 dE = (svk ? 0.5 : 1.0) * (dF.transpose() * F + F.transpose() * dF);
  Mat3 dPt;
  if (opt_.law) {
    const materials::MaterialFrame* frame =
        opt_.frames.empty() ? nullptr : &opt_.frames[static_cast<std::size_t>(i)];
    dPt = V * opt_.law->first_piola_derivative(F, dF, frame);
  } else {
    const Mat3 dS = lambda_ * dE.trace() * I + 2.0 * mu_ * dE;
    dPt = (svk ? V : 2.0 * V) * (dF * S + F * dS);
  }
  if (opt_.volume_stiffness_pa > 0.0) {
    const double J = F.determinant();
    const Mat3 cof = cofactor(F);
    const double dJ = cof.cwiseProduct(dF).sum();
    dPt += opt_.volume_stiffness_pa * V * (dJ * cof + (J - 1.0) * cofactor_derivative(F, dF));
  }
  return dPt;
}

// With d_ij = w_ij A_i^{-1} X_ij, the stabiliser's fit terms are w_ij F_i X_ij = F_i A_i d_ij and
// sum_j w_ij X_ij = -A_i d_ii, so its forces fold into the stress gather:
//   f_k = -Q_k d_kk - sum_{i: k in N_i} Q_i d_ik + own_k - sum_{i: k in N_i} c_i w_ik (y_k - y_i),
//   Q_i = Ptilde_i - c_i F_i A_i,   own_k = c_k sum_j w_kj (y_j - y_k).
// One pass over the transposed pairs, one 3x3 product and one axpy per pair.
// With Gauss points (R non-null) the stresses conjugate to dF_i/du_k, R_i,k, are gathered with e_ik,k the
// same way.
void PointPrimitiveEnergy::folded_gather(const std::vector<Mat3>& Q, const std::vector<Mat3>* R,
                                         const Vec3Array& own, const Vec3Array& y, Vec3Array& out) const {
  const Index n = disc_.num_nodes();
  const PairTable& T = disc_.transposed();
  const bool stab = folded_stab_;
  const std::size_t G = static_cast<std::size_t>(disc_.point_directions());
  out.resize(n);
#pragma omp parallel for schedule(static) if (n >= kParallelMinNodes)
  for (Index k = 0; k < n; ++k) {
    Vec3 f = -(Q[k] * disc_.self_d()[k]);
    if (R)
      for (std::size_t c = 0; c < G; ++c)
        f.noalias() -=
            (*R)[static_cast<std::size_t>(k) * G + c] * disc_.self_e()[static_cast<std::size_t>(k) * G + c];
    Vec3 pull = Vec3::Zero();
    const Vec3 yk = y[k];
    for (Index e = T.row_start[k], end = T.row_start[k + 1]; e < end; ++e) {
      const Index i = T.col[e];
      f.noalias() -= Q[i] * T.d[e];
      if (R)
        for (std::size_t c = 0; c < G; ++c)
          f.noalias() -= (*R)[static_cast<std::size_t>(i) * G + c] * T.e[static_cast<std::size_t>(e) * G + c];
      if (stab) pull += stab_cw_[e] * (yk - y[i]);
    }
    out[k] = stab ? Vec3(f + own[k] - pull) : f;
  }
}

// Pass 1 for node i: the gradient sum_j (y_j - y_i) d_ij^T and, for the stabiliser, sum_j w_ij (y_j - y_i)
// and sum_j w_ij |y_j - y_i|^2 from the same differences.
Mat3 PointPrimitiveEnergy::gradient_and_moments(Index i, const Vec3Array& y, Vec3& weighted_sum,
                                                double& weighted_squares) const {
  const PairTable& P = disc_.pairs();
  const Index* col = P.col.data();
  const Vec3* d = P.d.data();
  const double* w = P.w.data();
  const Vec3 yi = y[i];
  Vec3 c0 = Vec3::Zero(), c1 = Vec3::Zero(), c2 = Vec3::Zero(), sw = Vec3::Zero();
  double sq = 0.0;
  for (Index e = P.row_start[i], end = P.row_start[i + 1]; e < end; ++e) {
    const Vec3 dy = y[col[e]] - yi;
    c0 += d[e].x() * dy;
    c1 += d[e].y() * dy;
    c2 += d[e].z() * dy;
    sw += w[e] * dy;
    sq += w[e] * dy.squaredNorm();
  }
  Mat3 G;
  G.col(0) = c0;
  G.col(1) = c1;
  G.col(2) = c2;
  weighted_sum = sw;
  weighted_squares = sq;
  return G;
}

double PointPrimitiveEnergy::stabilizer_energy(const std::vector<Mat3>& F, const Vec3Array& x) const {
  if (opt_.stabilizer_alpha <= 0.0) return 0.0;
  if (stab_matrix_) {
    Workspace& ws = workspace(disc_.num_nodes());
    for (std::size_t i = 0; i < x.size(); ++i) ws.u[i] = x[i] - disc_.rest_positions()[i];
    return stab_matrix_->energy(ws.u);
  }
  const PairTable& P = disc_.pairs();
  const Vec3Array& X = disc_.rest_positions();
  double U = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : U) if (disc_.num_nodes() >= kParallelMinNodes)
  for (Index i = 0; i < disc_.num_nodes(); ++i) {
    double s = 0.0;
    for (Index e = P.row_start[i]; e < P.row_start[i + 1]; ++e) {
      const Index j = P.col[e];
      s += P.w[e] * ((x[j] - x[i]) - F[i] * (X[j] - X[i])).squaredNorm();
    }
    U += 0.5 * stab_c_[i] * s;
  }
  return U;
}

EnergyBreakdown PointPrimitiveEnergy::energy(const Vec3Array& x) const {
  const Index n = disc_.num_nodes();
  const int points = disc_.energy_points();
  std::vector<Mat3> F(n);
  double strain = 0.0, volume = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : strain, volume) if (n >= kParallelMinNodes)
  for (Index i = 0; i < n; ++i) {
    F[i] = disc_.deformation_gradient(i, x);
    Mat3 D[Discretization::kMaxPointDirections];
    disc_.deformation_gradient_derivatives(i, x, D);
    EnergyBreakdown e;
    for (int q = 0; q < points; ++q)
      weighted_stress(i, disc_.point_gradient(i, q, F[i], D), disc_.volumes()[i] / points, &e);
    strain += e.strain;
    volume += e.volume;
  }
  EnergyBreakdown out;
  out.strain = strain;
  out.volume = volume;
  out.stabilizer = stabilizer_energy(F, x);
  return out;
}

// Point q's stress (or its derivative) P pulls on F_i (into Q_i) and, times the point's offsets, on the
// gradient's derivatives dF_i/du_k (into R_i,k).
void PointPrimitiveEnergy::add_point_stress(Index i, int q, const Mat3& P, Mat3& Q, Mat3* R) const {
  Q += P;
  for (int c = 0; c < disc_.point_directions(); ++c) R[c] += disc_.point_offset(i, q, c) * P;
}

double PointPrimitiveEnergy::forces(const Vec3Array& x, Vec3Array& f, bool with_energy) const {
  const Index n = disc_.num_nodes();
  const int points = disc_.energy_points(), G = disc_.point_directions();
  Workspace& ws = workspace(n);
  const bool stab = folded_stab_;
  double strain = 0.0, volume = 0.0, stabilizer = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : strain, volume, stabilizer) if (n >= kParallelMinNodes)
  for (Index i = 0; i < n; ++i) {
    Vec3 sw;
    double sq;
    const Mat3 F = gradient_and_moments(i, x, sw, sq);
    EnergyBreakdown e;
    if (points == 1) {
      ws.Q[i] = weighted_stress(i, F, disc_.volumes()[i], &e);
    } else {
      // Each point's stress pulls on F_i and, times its offsets, on the derivatives dF_i/du_k.
      Mat3 D[Discretization::kMaxPointDirections];
      disc_.deformation_gradient_derivatives(i, x, D);
      ws.Q[i].setZero();
      Mat3* R = &ws.R[static_cast<std::size_t>(i) * G];
      for (int c = 0; c < G; ++c) R[c].setZero();
      for (int q = 0; q < points; ++q) {
        const Mat3 P = weighted_stress(i, disc_.point_gradient(i, q, F, D), disc_.volumes()[i] / points, &e);
        add_point_stress(i, q, P, ws.Q[i], R);
      }
    }
    strain += e.strain;
    volume += e.volume;
    if (stab) {
      const Mat3 FcA = F * stab_cA_[i];
      ws.Q[i] -= FcA;
      ws.own[i] = stab_c_[i] * sw;
      // c_i/2 sum_j w_ij |y_ij - F_i X_ij|^2 expanded with the fit's normal equations: c_i/2 (sum_j w_ij
      // |y_ij|^2
      // - F_i : F_i A_i). A difference of two terms, so for a report; energy() sums the residuals themselves.
      stabilizer += 0.5 * (stab_c_[i] * sq - F.cwiseProduct(FcA).sum());
    }
  }
  folded_gather(ws.Q, points > 1 ? &ws.R : nullptr, ws.own, x, f);
  if (stab_matrix_) {
    const Vec3Array& X = disc_.rest_positions();
    for (Index i = 0; i < n; ++i)
      ws.u[static_cast<std::size_t>(i)] = x[static_cast<std::size_t>(i)] - X[static_cast<std::size_t>(i)];
    if (with_energy)
      stabilizer += stab_matrix_->add_product_and_energy(ws.u, f, -1.0);  // f_hg = -K u
    else
      stab_matrix_->add_product(ws.u, f, -1.0);
  }
  return with_energy ? strain + volume + stabilizer : std::numeric_limits<double>::quiet_NaN();
}

PointPrimitiveEnergy::Linearization PointPrimitiveEnergy::linearize(const Vec3Array& x) const {
  const Index n = disc_.num_nodes();
  const int points = disc_.energy_points();
  Linearization lin;
  lin.F.resize(static_cast<std::size_t>(n * points));
  lin.S.resize(static_cast<std::size_t>(n * points));
#pragma omp parallel for schedule(static) if (n >= kParallelMinNodes)
  for (Index i = 0; i < n; ++i) {
    const Mat3 F = disc_.deformation_gradient(i, x);
    Mat3 D[Discretization::kMaxPointDirections];
    disc_.deformation_gradient_derivatives(i, x, D);
    for (int q = 0; q < points; ++q) {
      const std::size_t p = static_cast<std::size_t>(i * points + q);
      lin.F[p] = disc_.point_gradient(i, q, F, D);
      if (!opt_.law) lin.S[p] = stress(lin.F[p]);
    }
  }
  return lin;
}

void PointPrimitiveEnergy::hessian_product(const Vec3Array& x, const Vec3Array& v, Vec3Array& out) const {
  hessian_product(linearize(x), v, out);
}

void PointPrimitiveEnergy::hessian_product(const Linearization& lin, const Vec3Array& v,
                                           Vec3Array& out) const {
  const Index n = disc_.num_nodes();
  const int points = disc_.energy_points(), G = disc_.point_directions();
  Workspace& ws = workspace(n);
  const bool stab = folded_stab_;
  // The forces are -(folded gather of Q(F(x)), x); F is linear in x and the stabiliser terms are linear in x,
  // so the product is the folded gather of dQ = dPtilde - c dF A and of v, negated.
#pragma omp parallel for schedule(static) if (n >= kParallelMinNodes)
  for (Index i = 0; i < n; ++i) {
    Vec3 sw;
    double sq;
    const Mat3 dF = gradient_and_moments(i, v, sw, sq);
    if (points == 1) {
      ws.Q[i] = weighted_stress_derivative(i, lin.F[i], lin.S[i], dF, disc_.volumes()[i]);
    } else {
      Mat3 dD[Discretization::kMaxPointDirections];
      disc_.deformation_gradient_derivatives(i, v, dD);
      ws.Q[i].setZero();
      Mat3* R = &ws.R[static_cast<std::size_t>(i) * G];
      for (int c = 0; c < G; ++c) R[c].setZero();
      for (int q = 0; q < points; ++q) {
        const std::size_t p = static_cast<std::size_t>(i * points + q);
        const Mat3 dP = weighted_stress_derivative(i, lin.F[p], lin.S[p], disc_.point_gradient(i, q, dF, dD),
                                                   disc_.volumes()[i] / points);
        add_point_stress(i, q, dP, ws.Q[i], R);
      }
    }
    if (stab) {
      ws.Q[i] -= dF * stab_cA_[i];
      ws.own[i] = stab_c_[i] * sw;
    }
  }
  folded_gather(ws.Q, points > 1 ? &ws.R : nullptr, ws.own, v, out);
  for (auto& o : out) o = -o;
  if (stab_matrix_) stab_matrix_->add_product(v, out, 1.0);
}

}  // namespace vascsim
