#include "vascsim/constraints/xpbd_projection.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace vascsim::constraints {

namespace {
void check_sizes(std::size_t n, std::size_t w, std::size_t disp, std::size_t dp, bool need_disp,
                 const char* who) {
  if (w != n || dp != n || (need_disp && disp != n) || (!need_disp && disp != 0 && disp != n))
    throw std::invalid_argument(std::string(who) +
                                ": gradients, inverse masses, displacements and corrections must have one "
                                "entry per node (displacements may be empty without damping)");
}
}  // namespace

double xpbd_delta_lambda(double C, double sum_w_grad2, double grad_dot_displacement, double lambda,
                         const XpbdParameters& params) {
  const double h = params.dt;
  const double alpha_tilde = params.compliance / (h * h);
  const double gamma = params.compliance * params.damping / h;  // = alpha~ beta~ / h, beta~ = h^2 beta
  const double denominator = (1.0 + gamma) * sum_w_grad2 + alpha_tilde;
  if (!(denominator > params.epsilon)) return 0.0;
  double delta = (-C - alpha_tilde * lambda - gamma * grad_dot_displacement) / denominator;
  if (params.unilateral && lambda + delta < 0.0) delta = -lambda;  // keep the accumulated lambda >= 0
  return delta;
}

double xpbd_project(double C, std::span<const Vec3> grad, std::span<const double> w,
                    std::span<const Vec3> displacement, const XpbdParameters& params, double& lambda,
                    std::span<Vec3> dp) {
  const bool damped = params.damping != 0.0 && params.compliance != 0.0;
  check_sizes(grad.size(), w.size(), displacement.size(), dp.size(), damped, "xpbd_project");
  double sum_w_grad2 = 0.0, grad_dot_disp = 0.0;
  for (std::size_t k = 0; k < grad.size(); ++k) {
    sum_w_grad2 += w[k] * grad[k].squaredNorm();
    if (damped) grad_dot_disp += grad[k].dot(displacement[k]);
  }
  const double delta = xpbd_delta_lambda(C, sum_w_grad2, grad_dot_disp, lambda, params);
  lambda += delta;
  for (std::size_t k = 0; k < grad.size(); ++k) dp[k] = (w[k] * delta) * grad[k];
  return delta;
}

double pbd_iteration_stiffness(double k, int iterations) {
  if (!(k >= 0.0 && k <= 1.0) || iterations < 1)
    throw std::invalid_argument("pbd_iteration_stiffness: need 0 <= k <= 1 and iterations >= 1");
  return 1.0 - std::pow(1.0 - k, 1.0 / static_cast<double>(iterations));
}

double pbd_project(double C, std::span<const Vec3> grad, std::span<const double> w, double k_prime,
                   std::span<Vec3> dp, double epsilon) {
  check_sizes(grad.size(), w.size(), 0, dp.size(), false, "pbd_project");
  double sum_w_grad2 = 0.0;
  for (std::size_t k = 0; k < grad.size(); ++k) sum_w_grad2 += w[k] * grad[k].squaredNorm();
  const double s = sum_w_grad2 > epsilon ? -k_prime * C / sum_w_grad2 : 0.0;
  for (std::size_t k = 0; k < grad.size(); ++k) dp[k] = (w[k] * s) * grad[k];
  return s;
}

Vec6 xpbd_block_project(const Vec6& c, std::span<const Mat63> J, std::span<const double> w,
                        std::span<const Vec3> displacement, const Mat6& compliance, double damping, double dt,
                        Vec6& lambda, std::span<Vec3> dp) {
  const bool damped = damping != 0.0 && !compliance.isZero(0.0);
  check_sizes(J.size(), w.size(), displacement.size(), dp.size(), damped, "xpbd_block_project");
  Mat6 JWJt = Mat6::Zero();
  Vec6 J_disp = Vec6::Zero();
  for (std::size_t k = 0; k < J.size(); ++k) {
    JWJt.noalias() += w[k] * (J[k] * J[k].transpose());
    if (damped) J_disp.noalias() += J[k] * displacement[k];
  }
  const Mat6 alpha_tilde = compliance / (dt * dt);
  const Mat6 gamma = compliance * (damping / dt);
  const Mat6 system = (Mat6::Identity() + gamma) * JWJt + alpha_tilde;
  const Vec6 rhs = -c - alpha_tilde * lambda - gamma * J_disp;
  // With damping the matrix is a product of SPD factors, not symmetric in general: use LU then.
  Vec6 delta;
  if (damped) {
    Eigen::FullPivLU<Mat6> lu(system);
    if (lu.rank() < 6)
      delta.setZero();
    else
      delta = lu.solve(rhs);
  } else {
    Eigen::LDLT<Mat6> ldlt(system);
    const double scale = system.diagonal().cwiseAbs().maxCoeff();
    const bool ok = ldlt.info() == Eigen::Success && ldlt.isPositive() &&
                    ldlt.vectorD().minCoeff() > 1e-14 * scale && scale > kDenominatorEpsilon;
    if (ok)
      delta = ldlt.solve(rhs);
    else
      delta.setZero();
  }
  lambda += delta;
  for (std::size_t k = 0; k < J.size(); ++k) dp[k] = w[k] * (J[k].transpose() * delta);
  return delta;
}

}  // namespace vascsim::constraints
