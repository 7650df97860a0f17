#pragma once
// The zero-energy-mode stabiliser as one constant matrix (docs/model/09-volume-term-and-stabiliser.md
// section 9.2):
//   U_hg = 1/2 sum over the three coordinates c of u_c^T K u_c,   K = sum_i c_i R_i^T W_i R_i,
// with R_i node i's fit residuals over its stencil (Discretization::fit_residual_operator), W_i = diag(w_ij)
// and u = x - X (K X = 0: the stabiliser vanishes on every field the fit reproduces). With the linear basis
// the energy folds the stabiliser into its stress gather at no extra cost; with the quadratic basis the fit's
// prediction is not F_i X_ij, the fold does not hold, and the energy applies this matrix instead: one sparse
// product per force or Hessian evaluation.

#include <Eigen/SparseCore>
#include <vector>

#include "vascsim/model/discretization.hpp"

namespace vascsim {

class StabilizerMatrix {
 public:
  /// c: the stabiliser coefficient of every node, N m^2 (PointPrimitiveEnergy::stabilizer_coefficients).
  /// quadratic: the residuals of a quadratic fit, whatever the basis (Discretization::fit_residual_operator).
  StabilizerMatrix(const Discretization& disc, const std::vector<double>& c, bool quadratic);

  /// out += sign * K v, coordinate by coordinate (v in m gives N).
  void add_product(const Vec3Array& v, Vec3Array& out, double sign) const;
  /// The same, and returns v . K v / 2 (J for v = u) from the same pass.
  double add_product_and_energy(const Vec3Array& v, Vec3Array& out, double sign) const;
  /// u . K u / 2, J for u in m.
  double energy(const Vec3Array& u) const;
  /// K itself (scalar, n x n, N/m: the stabiliser's Hessian is K times the 3 x 3 identity).
  const Eigen::SparseMatrix<double, Eigen::RowMajor, int>& matrix() const { return K_; }
  /// Stored nonzeros of the scalar n x n matrix K.
  std::int64_t nonzeros() const { return K_.nonZeros(); }

 private:
  Eigen::SparseMatrix<double, Eigen::RowMajor, int> K_;
};

}  // namespace vascsim
