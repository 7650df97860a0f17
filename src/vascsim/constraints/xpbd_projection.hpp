#pragma once
// The one projection routine shared by every position-based constraint (docs/model/19-position-based.md
// section 19.5 and docs/model/16-deviations.md, E9).
//
// A constraint kernel supplies only its value C and its gradients grad_k C (iMSTK / Bender style, see
// STYLE.md); the routines here turn them into position corrections:
//
//  * XPBD (Macklin, Mueller, Chentanez 2016, "XPBD: Position-Based Simulation of Compliant Constrained
//    Dynamics", MIG 2016), damped form, their Eq. 26:
//      \Delta\lambda = \frac{-C - \tilde\alpha\lambda - \gamma \nabla C (p - x_{prev})}
//                           {(1+\gamma)\sum_k w_k |\nabla_k C|^2 + \tilde\alpha},
//      \tilde\alpha = \alpha / h^2,\ \tilde\beta = h^2 \beta,\ \gamma = \tilde\alpha\tilde\beta / h =
//      \alpha\beta / h, \Delta p_k = w_k \nabla_k C \, \Delta\lambda .
//    lambda is accumulated over the iterations of one (sub)step and reset to 0 by the caller once per
//    step, never per iteration (a per-iteration reset silently turns a compliant constraint rigid).
//  * PBD as printed in the paper (Zhang et al. 2021 Eq. 12 = Mueller et al. 2007, "Position Based
//    Dynamics", JVCIR 18(2), section 3.3):
//      \Delta p_k = -k' \frac{C}{\sum_j w_j |\nabla_j C|^2} w_k \nabla_k C,\quad k' = 1 - (1-k)^{1/n}.
//
// Units. lambda has units kg·m^2/[C]: for a length constraint (C in m, |grad C| = 1) lambda is in kg·m
// and lambda/h^2 is a force in N. The compliance alpha is the inverse stiffness of the
// energy U = C^2 / (2 alpha): m/N for a length constraint, 1/(N·m) = 1/J for a dimensionless one. The
// damping beta is a viscous coefficient in the same "per C" units: the dissipative force is
// -beta grad C (grad C . v), N·s/m for a length constraint. As in Macklin's formulation, damping acts only
// on compliant constraints (gamma = alpha beta / h vanishes for alpha = 0).
//
// Constraint force (for haptics, iMSTK): the force the constraint exerts on node k during the step is
//     f_k = \lambda \nabla_k C / h^2            (N)
// with lambda the value accumulated over the step. For an elastic constraint at convergence
// lambda = -C h^2/alpha, so f_k = -(C/alpha) grad_k C = -dU/dx_k. For a one-sided contact C = phi - r >= 0,
// lambda >= 0 and the tissue node is pushed along +grad C = n; the reaction on the rigid tool is -f_k.

#include <array>
#include <cstddef>
#include <span>

#include <Eigen/Core>

#include "vascsim/core/types.hpp"

namespace vascsim::constraints {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Mat63 = Eigen::Matrix<double, 6, 3>;

/// Denominator guard: a projection whose denominator (1+gamma) sum w|grad C|^2 + alpha~ (or the PBD
/// sum w|grad C|^2) is <= this value is skipped (zero correction, Delta lambda = 0). It fires only when
/// every involved node is fixed (w = 0) or the gradient vanishes (e.g. a coincident pair, or the 0/0 of a
/// double-root constraint at rest, docs/model/16-deviations.md, E11). Units are those of the denominator
/// (1/kg for a unit gradient); project masses are >= 1e-12 kg, so w|grad C|^2 of a live constraint is >>
/// 1e-30.
inline constexpr double kDenominatorEpsilon = 1e-30;

/// Value and gradients of a scalar constraint over N nodes (the output of every scalar kernel).
template <std::size_t N>
struct ScalarConstraint {
  double value = 0.0;          ///< C, in the constraint's units (m for a length)
  std::array<Vec3, N> grad{};  ///< grad_k C, one per involved node
};

struct XpbdParameters {
  double compliance = 0.0;  ///< alpha >= 0, inverse stiffness ([C]^2/J; m/N for a length constraint)
  double damping = 0.0;     ///< beta >= 0 (J·s/[C]^2; N·s/m for a length constraint), Macklin 2016 Eq. 26
  double dt = 1e-3;         ///< h, the (sub)step length, s
  bool unilateral = false;  ///< inequality C >= 0: the accumulated lambda is clamped to lambda >= 0
  double epsilon = kDenominatorEpsilon;  ///< denominator guard (see kDenominatorEpsilon)
};

/// Scalar core of the XPBD update (Macklin 2016 Eq. 26): Delta lambda from the constraint value C, the
/// generalised inverse mass sum_k w_k |grad_k C|^2 (passed in so closed forms, e.g. the per-spring
/// barycentre 1/m_a - 1/M, can be used), grad C . (p - x_prev) (only used when damping > 0) and the
/// accumulated lambda. Does NOT update lambda. For unilateral constraints the result is clamped so that
/// lambda + Delta lambda >= 0. Returns 0 if the denominator is <= epsilon.
double xpbd_delta_lambda(double C, double sum_w_grad2, double grad_dot_displacement, double lambda,
                         const XpbdParameters& params);

/// Full XPBD projection of one scalar constraint over n nodes.
///   grad[k] = grad_k C, w[k] = inverse mass (0 for fixed nodes), displacement[k] = p_k - x_prev_k (may be
///   empty when params.damping == 0 or params.compliance == 0), lambda: accumulated multiplier (in/out),
///   dp[k]: output corrections Delta p_k = w_k grad_k C Delta lambda (overwritten, not added). Returns Delta
///   lambda.
/// Throws std::invalid_argument on mismatched sizes.
double xpbd_project(double C, std::span<const Vec3> grad, std::span<const double> w,
                    std::span<const Vec3> displacement, const XpbdParameters& params, double& lambda,
                    std::span<Vec3> dp);

template <std::size_t N>
double xpbd_project(const ScalarConstraint<N>& c, const std::array<double, N>& w,
                    std::span<const Vec3> displacement, const XpbdParameters& params, double& lambda,
                    std::array<Vec3, N>& dp) {
  return xpbd_project(c.value, std::span<const Vec3>(c.grad), std::span<const double>(w), displacement,
                      params, lambda, std::span<Vec3>(dp));
}

/// Mueller 2007's per-iteration stiffness k' = 1 - (1 - k)^{1/n}, so that n Gauss-Seidel iterations of
/// one linear constraint remove the fraction k of its error (docs/model/16-deviations.md, E9). k in [0, 1], n
/// >= 1.
double pbd_iteration_stiffness(double k, int iterations);

/// PBD projection as printed (paper Eq. 12, Mueller 2007 section 3.3):
///   Delta p_k = -k' C w_k grad_k C / sum_j w_j |grad_j C|^2   (written to dp, overwritten).
/// Returns the multiplier-equivalent s = -k' C / sum w|grad C|^2 (so Delta p_k = s w_k grad_k C), or 0 if
/// the denominator is <= epsilon.
double pbd_project(double C, std::span<const Vec3> grad, std::span<const double> w, double k_prime,
                   std::span<Vec3> dp, double epsilon = kDenominatorEpsilon);

template <std::size_t N>
double pbd_project(const ScalarConstraint<N>& c, const std::array<double, N>& w, double k_prime,
                   std::array<Vec3, N>& dp, double epsilon = kDenominatorEpsilon) {
  return pbd_project(c.value, std::span<const Vec3>(c.grad), std::span<const double>(w), k_prime,
                     std::span<Vec3>(dp), epsilon);
}

/// Force the constraint exerts on node k over the step: f_k = lambda grad_k C / h^2, N (sign: see the file
/// comment; the reaction on a rigid body whose surface defines C is -f_k).
inline Vec3 constraint_force(double lambda, const Vec3& grad_k, double dt) {
  return (lambda / (dt * dt)) * grad_k;
}

/// XPBD projection of a 6-component (block) constraint c(x) in R^6 over n nodes, solved as one 6x6 system
/// (Macklin 2016 Eq. 26 in matrix form, used by the meshless strain constraint,
/// docs/model/19-position-based.md (A)):
///   [(I + Gamma) J W J^T + alpha~] Delta lambda = -c - alpha~ lambda - Gamma J (p - x_prev),
///   alpha~ = compliance / h^2,  Gamma = compliance * damping / h,  Delta p_k = w_k J_k^T Delta lambda.
/// J[k] = dc/dx_k (6x3), w[k] inverse masses, displacement[k] = p_k - x_prev_k (may be empty when
/// damping == 0 or compliance == 0), compliance: symmetric positive semi-definite 6x6, lambda: accumulated
/// (in/out), dp: corrections (overwritten). The system is solved by LDLT; if the matrix is not positive
/// definite (rigid block, alpha = 0, with a rank-deficient J) the correction is skipped and 0 returned.
Vec6 xpbd_block_project(const Vec6& c, std::span<const Mat63> J, std::span<const double> w,
                        std::span<const Vec3> displacement, const Mat6& compliance, double damping, double dt,
                        Vec6& lambda, std::span<Vec3> dp);

}  // namespace vascsim::constraints
