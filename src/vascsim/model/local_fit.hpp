#pragma once
// The local fit behind the point-primitive gradient (Eqs. 2-4, docs/model/05-local-fit.md sections 5
// and 5.1): node i's neighbour differences y_j - y_i are fitted, weighted by w_ij, by a polynomial in X_ij =
// X_j - X_i without a constant term, and the fitted first derivatives are the gradient at the node.
//
// - Linear basis (the paper's Eq. 4): y_j - y_i ~ G X_ij, moment matrix A_i = sum_j w_ij X_ij X_ij^T, and
//   d_ij = w_ij A_i^{-1} X_ij. Exact for affine fields. Its gradient is that of the best affine fit over the
//   neighbourhood, i.e. the gradient near the neighbourhood's weighted centroid: on a node of a wall's
//   surface layer, whose neighbours all lie on one side, a bending field's gradient comes out as the one a
//   fraction of the wall thickness deeper, too small, and a thin wall is too soft.
// - Quadratic basis (second-order consistency, as in higher-order reproducing-kernel and MLS methods):
//   y_j - y_i ~ G X_ij + 1/2 H : X_ij X_ij, i.e. 9 monomials p(X) = (x, y, z, x^2, xy, xz, y^2, yz, z^2)
//   (scaled by the support radius s so that every entry is O(1)), moment matrix B_i = sum_j w_ij p_ij p_ij^T
//   (9 x 9), and d_ij = the first three entries of w_ij B_i^{-1} p_ij, divided by s. Exact for quadratic
//   fields, so the gradient is the one at the node itself: bending is right on every layer of a thin wall.
// - Wall-quadratic basis (docs/model/05-local-fit.md section 5.2): the quadratic fit without the through-wall
// square, in the frame
//   of the wall's normal (8 monomials), so that it needs only the two layers a surface node's support holds.
//
// Every way F_i = sum_j (x_j - x_i) d_ij^T, so the energy, its forces and its Hessian are the same code for
// all.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "vascsim/core/types.hpp"

namespace vascsim {

enum class GradientBasis {
  Linear,        ///< Eq. 4 as in the paper (default)
  Quadratic,     ///< second-order consistent fit (docs/model/05-local-fit.md section 5.1)
  WallQuadratic  ///< the quadratic fit without the through-wall square (docs/model/05-local-fit.md
                 ///< section 5.2)
};

/// Whether a basis fits second derivatives (and so keeps the fit's coefficients per pair).
inline bool fits_curvature(GradientBasis basis) {
  return basis != GradientBasis::Linear;
}

/// Quadratic monomials of X / s: (x, y, z, x^2, xy, xz, y^2, yz, z^2) of the scaled vector.
inline Vec9 quadratic_monomials(const Vec3& X, double s) {
  const Vec3 y = X / s;
  Vec9 p;
  p << y.x(), y.y(), y.z(), y.x() * y.x(), y.x() * y.y(), y.x() * y.z(), y.y() * y.y(), y.y() * y.z(),
      y.z() * y.z();
  return p;
}

/// The wall-quadratic basis's monomials of X / s (docs/model/05-local-fit.md section 5.2): the linear ones in
/// the global frame, then, in the frame (t1, t2, n) of the wall's unit normal n, t1^2, t1 t2, t2^2, t1 n, t2
/// n; the last entry is 0 (the through-wall square n^2 is left out). The choice of t1, t2 in the tangent
/// plane does not change the fit: either set of monomials spans the same functions.
inline Vec9 wall_quadratic_monomials(const Vec3& X, double s, const Vec3& normal) {
  const Vec3 y = X / s;
  const Vec3 t1 = normal.unitOrthogonal();
  const Vec3 t2 = normal.cross(t1);
  const double a = y.dot(t1), b = y.dot(t2), c = y.dot(normal);
  Vec9 p;
  p << y.x(), y.y(), y.z(), a * a, a * b, b * b, a * c, b * c, 0.0;
  return p;
}

/// How the gradient a fit gives changes along a direction: for the fit y(X) ~ sum_m a_m p_m(X / s) of a
/// curvature basis, the derivative of its gradient at X = r u along r (u a unit vector) is (1/s^2) sum_m a_m
/// H_m u, with H_m the constant Hessian of monomial p_m (zero for the linear ones). Returns the 9 x 3 matrix
/// whose row m is (H_m u)^T, so that a pair's fit coefficients c_ij give the pair's gradient-derivative
/// vector c_ij^T M / s^2.
inline Eigen::Matrix<double, 9, 3> monomial_hessians_along(GradientBasis basis, const Vec3& u,
                                                           const Vec3& normal) {
  Eigen::Matrix<double, 9, 3> M = Eigen::Matrix<double, 9, 3>::Zero();
  if (basis == GradientBasis::WallQuadratic) {
    // In the frame (t1, t2, n): the Hessians of a^2, ab, b^2, an, bn applied to u.
    const Vec3 t1 = normal.unitOrthogonal();
    const Vec3 t2 = normal.cross(t1);
    const double a = u.dot(t1), b = u.dot(t2), c = u.dot(normal);
    M.row(3) = 2.0 * a * t1.transpose();
    M.row(4) = (b * t1 + a * t2).transpose();
    M.row(5) = 2.0 * b * t2.transpose();
    M.row(6) = (c * t1 + a * normal).transpose();
    M.row(7) = (c * t2 + b * normal).transpose();
  } else if (basis == GradientBasis::Quadratic) {
    // x^2, xy, xz, y^2, yz, z^2 in the global frame.
    M.row(3) << 2.0 * u.x(), 0.0, 0.0;
    M.row(4) << u.y(), u.x(), 0.0;
    M.row(5) << u.z(), 0.0, u.x();
    M.row(6) << 0.0, 2.0 * u.y(), 0.0;
    M.row(7) << 0.0, u.z(), u.y();
    M.row(8) << 0.0, 0.0, 2.0 * u.z();
  }
  return M;
}

}  // namespace vascsim
