#pragma once
// Small 3x3 tensor helpers shared by the point-primitive energy, the hyperelastic laws and the tet
// constraints (header-only, inlined in the hot paths).

#include <Eigen/Eigenvalues>

#include "vascsim/core/types.hpp"

namespace vascsim {

/// cof(F) = det(F) F^{-T} = dJ/dF, columns [F_1 x F_2, F_2 x F_0, F_0 x F_1] (F_c = column c). Not
/// adj(F) = cof(F)^T, which differs for every non-symmetric F (docs/model/09-volume-term-and-stabiliser.md
/// section 9.1). Defined for every F, including singular and inverted ones.
inline Mat3 cofactor(const Mat3& F) {
  Mat3 C;
  C.col(0) = F.col(1).cross(F.col(2));
  C.col(1) = F.col(2).cross(F.col(0));
  C.col(2) = F.col(0).cross(F.col(1));
  return C;
}

/// d cof(F) along dF (product rule on the column cross products); cof is quadratic in F.
inline Mat3 cofactor_derivative(const Mat3& F, const Mat3& dF) {
  Mat3 C;
  C.col(0) = dF.col(1).cross(F.col(2)) + F.col(1).cross(dF.col(2));
  C.col(1) = dF.col(2).cross(F.col(0)) + F.col(2).cross(dF.col(0));
  C.col(2) = dF.col(0).cross(F.col(1)) + F.col(0).cross(dF.col(1));
  return C;
}

/// Double contraction A : B = sum_kl A_kl B_kl.
inline double ddot(const Mat3& A, const Mat3& B) {
  return A.cwiseProduct(B).sum();
}

/// A symmetric S with its negative eigenvalues set to zero; S itself (to the bit) when it has none. Positive
/// definite by its leading minors (Sylvester) needs no eigendecomposition: most stresses under load.
inline Mat3 positive_part(const Mat3& S) {
  if (S(0, 0) > 0.0 && S(0, 0) * S(1, 1) - S(0, 1) * S(1, 0) > 0.0 && S.determinant() > 0.0) return S;
  Eigen::SelfAdjointEigenSolver<Mat3> es;
  es.computeDirect(S);
  if (es.eigenvalues().minCoeff() >= 0.0) return S;
  return es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).asDiagonal() * es.eigenvectors().transpose();
}

}  // namespace vascsim
