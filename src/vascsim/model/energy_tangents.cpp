#include "vascsim/model/energy_tangents.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "vascsim/core/parallel.hpp"
#include "vascsim/core/tensor_algebra.hpp"

namespace vascsim {

namespace {

// vec index of a 3x3 entry (a, c): column-major, as Eigen stores Mat3.
constexpr int vec_index(int a, int c) {
  return a + 3 * c;
}

// The 9x9 matrix of a linear map dF -> dP, column (b, d) = vec(dP(e_b e_d^T)).
template <class Fn>
Mat9 tangent_of(const Fn& dP) {
  Mat9 C;
  for (int d = 0; d < 3; ++d)
    for (int b = 0; b < 3; ++b) {
      Mat3 dF = Mat3::Zero();
      dF(b, d) = 1.0;
      const Mat3 P = dP(dF);
      C.col(vec_index(b, d)) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(P.data());
    }
  return C;
}

Mat9 point_tangent(const PointPrimitiveEnergy& energy, Index i, const Mat3& F, int points,
                   TangentProjection projection) {
  const Discretization& disc = energy.discretization();
  const EnergyOptions& eo = energy.options();
  const double lambda = energy.strain_lambda(), mu = energy.shear_modulus(), kv = eo.volume_stiffness_pa;
  // Literal strain (docs/model/07-strain-stress-energy.md): eps = 2E and sigma = 2S, so U_lit = 4 U_SVK and
  // its tangent is 4x.
  const double svk_scale = eo.strain == StrainMeasure::GreenHalf ? 1.0 : 4.0;
  const Mat3 I = Mat3::Identity();
  Mat9 C;
  if (eo.law) {
    const materials::MaterialFrame* frame =
        eo.frames.empty() ? nullptr : &eo.frames[static_cast<std::size_t>(i)];
    C = tangent_of([&](const Mat3& dF) { return eo.law->first_piola_derivative(F, dF, frame); });
  } else {
    // SVK: P = F S, S = lambda tr(E) I + 2 mu E, E = 1/2 (F^T F - I) (Eqs. 5-7 with the 1/2).
    const Mat3 E = 0.5 * (F.transpose() * F - I);
    Mat3 S = lambda * E.trace() * I + 2.0 * mu * E;
    if (projection == TangentProjection::ClampedStress) {
      // dF : dF S+ >= 0 and dF : F (lambda tr(dE) I + 2 mu dE) = lambda tr(dE)^2 + 2 mu |dE|^2 >= 0.
      S = positive_part(S);
    }
    C = svk_scale * tangent_of([&](const Mat3& dF) {
          const Mat3 dE = 0.5 * (dF.transpose() * F + F.transpose() * dF);
          return Mat3(dF * S + F * (lambda * dE.trace() * I + 2.0 * mu * dE));
        });
  }
  if (kv > 0.0) {
    // docs/model/09-volume-term-and-stabiliser.md section 9.1: P_v = k_v (J - 1) cof(F), dP_v = k_v [(cof :
    // dF) cof + (J - 1) dcof[dF]].
    const double J = F.determinant();
    const Mat3 cof = cofactor(F);
    C += tangent_of([&](const Mat3& dF) {
      return Mat3(kv * (cof.cwiseProduct(dF).sum() * cof + (J - 1.0) * cofactor_derivative(F, dF)));
    });
  }
  // Exact tangents are symmetric; symmetrise the rounding (into a new matrix: C^T must not alias C).
  const Mat9 Csym = (0.5 * disc.volumes()[static_cast<std::size_t>(i)] / points) * (C + C.transpose());
  if (projection != TangentProjection::Spectral) return Csym;
  // A positive definite tangent (every node at rest, most under load) is its own projection: a 9x9 Cholesky
  // tells that for a tenth of an eigendecomposition.
  if (Eigen::LLT<Mat9>(Csym).info() == Eigen::Success) return Csym;
  Eigen::SelfAdjointEigenSolver<Mat9> es(Csym);
  if (!(es.eigenvalues()(0) < 0.0)) return Csym;
  return es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).asDiagonal() * es.eigenvectors().transpose();
}

void node_tangents(const PointPrimitiveEnergy& energy, const Vec3Array& x, TangentProjection projection,
                   Index i, Mat9Array& out) {
  const Discretization& disc = energy.discretization();
  const int points = disc.energy_points();
  // F_i and its derivatives dF_i/du_k once per node; each energy point q has F_i + sum_k o_qk dF_i/du_k.
  const Mat3 Fi = disc.deformation_gradient(i, x);
  Mat3 Di[Discretization::kMaxPointDirections];
  disc.deformation_gradient_derivatives(i, x, Di);
  for (int q = 0; q < points; ++q)
    out[static_cast<std::size_t>(i * points + q)] =
        point_tangent(energy, i, disc.point_gradient(i, q, Fi, Di), points, projection);
}

}  // namespace

TangentProjection positive_projection(const PointPrimitiveEnergy& energy) {
  const EnergyOptions& o = energy.options();
  return !o.law && o.strain == StrainMeasure::GreenHalf && o.volume_stiffness_pa == 0.0
             ? TangentProjection::ClampedStress
             : TangentProjection::Spectral;
}

void energy_tangents(const PointPrimitiveEnergy& energy, const Vec3Array& x, TangentProjection projection,
                     Mat9Array& out, const std::vector<Index>* nodes) {
  if (projection == TangentProjection::ClampedStress && positive_projection(energy) != projection)
    projection = TangentProjection::Spectral;
  const Discretization& disc = energy.discretization();
  const Index n = disc.num_nodes();
  out.resize(static_cast<std::size_t>(n) * static_cast<std::size_t>(disc.energy_points()));
  const std::size_t count = nodes ? nodes->size() : static_cast<std::size_t>(n);
#pragma omp parallel for schedule(static) if (count >= static_cast <std::size_t>(kParallelMinNodes))
  for (std::size_t k = 0; k < count; ++k)
    node_tangents(energy, x, projection, nodes ? (*nodes)[k] : static_cast<Index>(k), out);
}

Mat3 tangent_block(const Mat9& C, const Vec3& dk, const Vec3& dl) {
  const Eigen::Matrix<double, 3, 9> U =
      dk[0] * C.middleRows<3>(0) + dk[1] * C.middleRows<3>(3) + dk[2] * C.middleRows<3>(6);
  return dl[0] * U.middleCols<3>(0) + dl[1] * U.middleCols<3>(3) + dl[2] * U.middleCols<3>(6);
}

}  // namespace vascsim
