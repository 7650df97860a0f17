#include "vascsim/model/point_primitive_energy.hpp"

#include <fmt/format.h>

#include "vascsim/core/error.hpp"
#include "vascsim/core/parallel.hpp"
#include "vascsim/core/tensor_algebra.hpp"

namespace vascsim {

PointPrimitiveEnergy::PointPrimitiveEnergy(const Discretization& disc, const EnergyOptions& options)
    : disc_(disc), opt_(options) {
  const Material& m = disc.material();
  mu_ = m.shear_modulus();
  lambda_ = m.lame_lambda() - opt_.volume_stiffness_pa;
  if (opt_.law) {
    if (opt_.strain != StrainMeasure::GreenHalf)
      throw InputError(fmt::format("energy: the literal strain (mueller_no_half) applies to the built-in SVK only, "
                                   "not to material law '{}'",
                                   opt_.law->name()));
    mu_ = opt_.law->small_strain_shear_modulus();
    lambda_ = opt_.law->small_strain_bulk_modulus() - 2.0 / 3.0 * mu_ - opt_.volume_stiffness_pa;
    if (opt_.law->needs_frame() && opt_.frames.size() != static_cast<std::size_t>(disc.num_nodes()))
      throw InputError(fmt::format("energy: material law '{}' needs a wall frame at every node (a vessel geometry)",
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
}

Mat3 PointPrimitiveEnergy::weighted_stress(Index i, const Mat3& F, EnergyBreakdown* e) const {
  const double V = disc_.volumes()[i];
  const Mat3 I = Mat3::Identity();
  Mat3 Pt;
  if (opt_.law) {
    const materials::MaterialFrame* frame = opt_.frames.empty() ? nullptr : &opt_.frames[static_cast<std::size_t>(i)];
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
    Pt = 2.0 * V * (F * sigma);  // Mueller's F_e = -2 v J sigma (MODEL.md 1.8)
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

Mat3 PointPrimitiveEnergy::weighted_stress_derivative(Index i, const Mat3& F, const Mat3& S, const Mat3& dF) const {
  const double V = disc_.volumes()[i];
  const Mat3 I = Mat3::Identity();
  // SVK: P = F S, S = lambda tr(E) I + 2 mu E, E = 1/2 (F^T F - I).
  // Literal: Ptilde = 2 V F sigma with sigma of eps = F^T F - I, i.e. "half" = 1 and a factor 2.
  const bool svk = opt_.strain == StrainMeasure::GreenHalf;
  const Mat3 dE = (svk ? 0.5 : 1.0) * (dF.transpose() * F + F.transpose() * dF);
  Mat3 dPt;
  if (opt_.law) {
    const materials::MaterialFrame* frame = opt_.frames.empty() ? nullptr : &opt_.frames[static_cast<std::size_t>(i)];
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

double PointPrimitiveEnergy::gather(const std::vector<Mat3>& Ptilde, const std::vector<Mat3>& F_fit,
                                    const Vec3Array& y, Vec3Array& out) const {
  const Index n = disc_.num_nodes();
  const PairTable& P = disc_.pairs();
  const PairTable& T = disc_.transposed();
  const Vec3Array& X = disc_.rest_positions();
  const bool stab = opt_.stabilizer_alpha > 0.0;
  out.resize(n);
  double stab_energy = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : stab_energy) if (n >= kParallelMinNodes)
  for (Index k = 0; k < n; ++k) {
    Vec3 f = -(Ptilde[k] * disc_.self_d()[k]);
    for (Index e = T.row_start[k]; e < T.row_start[k + 1]; ++e) f -= Ptilde[T.col[e]] * T.d[e];
    if (stab) {
      // Own fit: f_k += c_k sum_j w_kj r_kj; fits of others: f_k -= c_i w_ik r_ik (MODEL.md 1.9b).
      // The same residuals give node k's stabiliser energy (c_k/2) sum_j w_kj |r_kj|^2.
      Vec3 own = Vec3::Zero();
      double own_energy = 0.0;
      for (Index e = P.row_start[k]; e < P.row_start[k + 1]; ++e) {
        const Index j = P.col[e];
        const Vec3 r = (y[j] - y[k]) - F_fit[k] * (X[j] - X[k]);
        own += P.w[e] * r;
        own_energy += P.w[e] * r.squaredNorm();
      }
      f += stab_c_[k] * own;
      stab_energy += 0.5 * stab_c_[k] * own_energy;
      for (Index e = T.row_start[k]; e < T.row_start[k + 1]; ++e) {
        const Index i = T.col[e];
        f -= stab_c_[i] * T.w[e] * ((y[k] - y[i]) - F_fit[i] * (X[k] - X[i]));
      }
    }
    out[k] = f;
  }
  return stab_energy;
}

double PointPrimitiveEnergy::stabilizer_energy(const std::vector<Mat3>& F, const Vec3Array& x) const {
  if (opt_.stabilizer_alpha <= 0.0) return 0.0;
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
  std::vector<Mat3> F(n);
  double strain = 0.0, volume = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : strain, volume) if (n >= kParallelMinNodes)
  for (Index i = 0; i < n; ++i) {
    F[i] = disc_.deformation_gradient(i, x);
    EnergyBreakdown e;
    weighted_stress(i, F[i], &e);
    strain += e.strain;
    volume += e.volume;
  }
  EnergyBreakdown out;
  out.strain = strain;
  out.volume = volume;
  out.stabilizer = stabilizer_energy(F, x);
  return out;
}

double PointPrimitiveEnergy::forces(const Vec3Array& x, Vec3Array& f) const {
  const Index n = disc_.num_nodes();
  std::vector<Mat3> F(n), Pt(n);
  double strain = 0.0, volume = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : strain, volume) if (n >= kParallelMinNodes)
  for (Index i = 0; i < n; ++i) {
    F[i] = disc_.deformation_gradient(i, x);
    EnergyBreakdown e;
    Pt[i] = weighted_stress(i, F[i], &e);
    strain += e.strain;
    volume += e.volume;
  }
  return strain + volume + gather(Pt, F, x, f);
}

PointPrimitiveEnergy::Linearization PointPrimitiveEnergy::linearize(const Vec3Array& x) const {
  const Index n = disc_.num_nodes();
  Linearization lin;
  lin.F.resize(n);
  lin.S.resize(n);
#pragma omp parallel for schedule(static) if (n >= kParallelMinNodes)
  for (Index i = 0; i < n; ++i) {
    lin.F[i] = disc_.deformation_gradient(i, x);
    if (!opt_.law) lin.S[i] = stress(lin.F[i]);
  }
  return lin;
}

void PointPrimitiveEnergy::hessian_product(const Vec3Array& x, const Vec3Array& v, Vec3Array& out) const {
  hessian_product(linearize(x), v, out);
}

void PointPrimitiveEnergy::hessian_product(const Linearization& lin, const Vec3Array& v, Vec3Array& out) const {
  const Index n = disc_.num_nodes();
  std::vector<Mat3> dPt(n), dF(n);
#pragma omp parallel for schedule(static) if (n >= kParallelMinNodes)
  for (Index i = 0; i < n; ++i) {
    dF[i] = disc_.deformation_gradient(i, v);  // F is linear in positions
    dPt[i] = weighted_stress_derivative(i, lin.F[i], lin.S[i], dF[i]);
  }
  // The stabiliser force is linear in the positions, so its Hessian applied to v is minus its force at v.
  gather(dPt, dF, v, out);
  for (auto& o : out) o = -o;
}

}  // namespace vascsim
