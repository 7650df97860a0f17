#include "vascsim/rod/lumen_contact.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <limits>

#include "vascsim/core/error.hpp"

namespace vascsim::rod {

namespace {

// Below this distance from the axis a node has no outward direction (and is far from any wall).
constexpr double kOnAxis = 1e-12;

// The penalty's shape in z = lambda / k + g (m), smoothed over the first `w` of penetration so that the
// energy is twice differentiable: the force k psi(z) grows as z^2 / 2w there, then linearly. With the plain
// max(0, z) a node flipping in and out of contact made Newton cycle (a wire pushed round the aorta's arch:
// residuals oscillating between 1e-5 and 1e-4 for a hundred iterations).
double psi(double z, double w) {
  return z <= 0.0 ? 0.0 : z < w ? 0.5 * z * z / w : z - 0.5 * w;
}
double dpsi(double z, double w) {
  return z <= 0.0 ? 0.0 : z < w ? z / w : 1.0;
}
double psi_integral(double z, double w) {  // the energy per k, m^2
  return z <= 0.0 ? 0.0 : z < w ? z * z * z / (6.0 * w) : 0.5 * z * z - 0.5 * w * z + w * w / 6.0;
}

}  // namespace

LumenContact::LumenContact(const Lumen& lumen, double rod_radius_m, double penalty_n_per_m)
    : lumen_(lumen), r_(rod_radius_m), k_(penalty_n_per_m), w_(0.01 * rod_radius_m) {
  if (!(rod_radius_m > 0.0) || !(penalty_n_per_m > 0.0))
    throw InputError(fmt::format("rod contact: the rod's radius {} m and the penalty {} N/m must be positive",
                                 rod_radius_m, penalty_n_per_m));
}

double LumenContact::energy(const CosseratRod& rod) const {
  lambda_.resize(static_cast<std::size_t>(rod.num_nodes()), 0.0);
  double e = 0.0;
  for (Index i = 0; i < rod.num_nodes(); ++i) {
    if (!checked(i)) continue;
    const double z = lambda_[static_cast<std::size_t>(i)] / k_ +
                     gap(lumen_.at(rod.positions()[static_cast<std::size_t>(i)]));
    e += k_ * psi_integral(z, w_);
  }
  return e;
}

void LumenContact::add_gradient(const CosseratRod& rod, Eigen::VectorXd& g) const {
  lambda_.resize(static_cast<std::size_t>(rod.num_nodes()), 0.0);
  for (Index i = 0; i < rod.num_nodes(); ++i) {
    if (!checked(i)) continue;
    const LumenPoint p = lumen_.at(rod.positions()[static_cast<std::size_t>(i)]);
    const double m = k_ * psi(lambda_[static_cast<std::size_t>(i)] / k_ + gap(p), w_);
    if (m > 0.0) g.segment<3>(CosseratRod::position_dof(i)) += m * p.outward;
  }
}

void LumenContact::add_hessian(const CosseratRod& rod, std::vector<Eigen::Triplet<double>>& t) const {
  lambda_.resize(static_cast<std::size_t>(rod.num_nodes()), 0.0);
  for (Index i = 0; i < rod.num_nodes(); ++i) {
    if (!checked(i)) continue;
    const LumenPoint p = lumen_.at(rod.positions()[static_cast<std::size_t>(i)]);
    const double z = lambda_[static_cast<std::size_t>(i)] / k_ + gap(p);
    const double m = k_ * psi(z, w_);
    if (m <= 0.0 || p.distance_m < kOnAxis) continue;
    // k n n^T, and the turn of the outward direction as the node moves across it: m (I - n n^T - t t^T) / d
    // (exact in a straight lumen; in a bend it leaves out the axis's curvature, a term of order m / R_bend).
    const Mat3 h = k_ * dpsi(z, w_) * p.outward * p.outward.transpose() +
                   m / p.distance_m *
                       (Mat3::Identity() - p.outward * p.outward.transpose() - p.axis * p.axis.transpose());
    const Index d = CosseratRod::position_dof(i);
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) t.emplace_back(d + a, d + b, h(a, b));
  }
}

void LumenContact::update_multipliers(const CosseratRod& rod) {
  lambda_.resize(static_cast<std::size_t>(rod.num_nodes()), 0.0);
  for (Index i = 0; i < rod.num_nodes(); ++i) {
    double& l = lambda_[static_cast<std::size_t>(i)];
    l = checked(i) ? k_ * psi(l / k_ + gap(lumen_.at(rod.positions()[static_cast<std::size_t>(i)])), w_)
                   : 0.0;
  }
}

double LumenContact::max_penetration(const CosseratRod& rod) const {
  double worst = -std::numeric_limits<double>::infinity();
  for (Index i = 0; i < rod.num_nodes(); ++i)
    if (checked(i)) worst = std::max(worst, gap(lumen_.at(rod.positions()[static_cast<std::size_t>(i)])));
  return worst;
}

Vec3Array LumenContact::forces(const CosseratRod& rod) const {
  lambda_.resize(static_cast<std::size_t>(rod.num_nodes()), 0.0);
  Vec3Array f(static_cast<std::size_t>(rod.num_nodes()), Vec3::Zero());
  for (Index i = 0; i < rod.num_nodes(); ++i) {
    if (!checked(i)) continue;
    const LumenPoint p = lumen_.at(rod.positions()[static_cast<std::size_t>(i)]);
    f[static_cast<std::size_t>(i)] =
        -k_ * psi(lambda_[static_cast<std::size_t>(i)] / k_ + gap(p), w_) * p.outward;
  }
  return f;
}

double worst_outside(const CosseratRod& rod, const std::vector<char>& outside, const Lumen& lumen,
                     double rod_radius_m) {
  double worst = -std::numeric_limits<double>::infinity();
  const Vec3Array& x = rod.positions();
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (outside[i]) continue;
    const LumenPoint p = lumen.at(x[i]);
    worst = std::max(worst, p.distance_m + rod_radius_m - p.radius_m);
    if (i > 0 && !outside[i - 1]) {
      const LumenPoint m = lumen.at(0.5 * (x[i] + x[i - 1]));
      worst = std::max(worst, m.distance_m + rod_radius_m - m.radius_m);
    }
  }
  return worst;
}

LumenSolveReport solve_in_lumen(CosseratRod& rod, const std::vector<char>& held, const Vec3Array& forces,
                                LumenContact& contact, double tolerance_m, int max_passes,
                                const RodStaticsOptions& options,
                                const std::vector<const RodPotential*>& others) {
  LumenSolveReport r;
  std::vector<const RodPotential*> all{&contact};
  all.insert(all.end(), others.begin(), others.end());
  int newton = 0;
  for (r.passes = 1;; ++r.passes) {
    r.statics = solve_rod_statics(rod, held, forces, options, all);
    newton += r.statics.newton_iterations;
    r.max_penetration_m = contact.max_penetration(rod);
    if (!r.statics.converged || r.max_penetration_m <= tolerance_m || r.passes >= max_passes) break;
    contact.update_multipliers(rod);
  }
  r.statics.newton_iterations = newton;
  return r;
}

}  // namespace vascsim::rod
