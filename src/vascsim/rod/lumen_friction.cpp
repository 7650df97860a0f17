#include "vascsim/rod/lumen_friction.hpp"

#include <fmt/format.h>
#include <cmath>

#include "vascsim/core/error.hpp"

namespace vascsim::rod {

LumenFriction::LumenFriction(double mu, double slip_m) : mu_(mu), e_(slip_m) {
  if (!(mu >= 0.0) || !std::isfinite(mu) || !(slip_m > 0.0) || !std::isfinite(slip_m))
    throw InputError(
        fmt::format("rod friction: mu {} must be at least 0 and the slip {} m positive", mu, slip_m));
}

void LumenFriction::begin_step(const CosseratRod& rod, const LumenContact& contact, const Lumen& lumen) {
  anchor_ = rod.positions();
  const Vec3Array f = contact.forces(rod);
  normal_.assign(anchor_.size(), Vec3::Zero());
  normal_force_.assign(anchor_.size(), 0.0);
  for (std::size_t i = 0; i < anchor_.size(); ++i) {
    normal_force_[i] = f[i].norm();
    if (normal_force_[i] > 0.0) normal_[i] = lumen.at(anchor_[i]).outward;
  }
}

double LumenFriction::energy(const CosseratRod& rod) const {
  double e = 0.0;
  for (std::size_t i = 0; i < anchor_.size(); ++i) {
    if (!(normal_force_[i] > 0.0)) continue;
    Vec3 u = rod.positions()[i] - anchor_[i];
    u -= u.dot(normal_[i]) * normal_[i];
    const double y = u.norm();
    e += mu_ * normal_force_[i] * (y < e_ ? 0.5 * y * y / e_ : y - 0.5 * e_);
  }
  return e;
}

void LumenFriction::add_gradient(const CosseratRod& rod, Eigen::VectorXd& g) const {
  for (std::size_t i = 0; i < anchor_.size(); ++i) {
    if (!(normal_force_[i] > 0.0)) continue;
    Vec3 u = rod.positions()[i] - anchor_[i];
    u -= u.dot(normal_[i]) * normal_[i];
    const double y = u.norm();
    const Vec3 grad = mu_ * normal_force_[i] * (y < e_ ? Vec3(u / e_) : Vec3(u / y));
    g.segment<3>(CosseratRod::position_dof(static_cast<Index>(i))) += grad;
  }
}

void LumenFriction::add_hessian(const CosseratRod& rod, std::vector<Eigen::Triplet<double>>& t) const {
  for (std::size_t i = 0; i < anchor_.size(); ++i) {
    if (!(normal_force_[i] > 0.0)) continue;
    const Vec3& n = normal_[i];
    const Mat3 T = Mat3::Identity() - n * n.transpose();
    Vec3 u = rod.positions()[i] - anchor_[i];
    u -= u.dot(n) * n;
    const double y = u.norm();
    // Sticking: mu lambda / e on the plane; sliding: mu lambda / y across the slip only (PSD).
    const Mat3 h = y < e_ ? Mat3(mu_ * normal_force_[i] / e_ * T)
                          : Mat3(mu_ * normal_force_[i] / y * (T - (u / y) * (u / y).transpose()));
    const Index d = CosseratRod::position_dof(static_cast<Index>(i));
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) t.emplace_back(d + a, d + b, h(a, b));
  }
}

}  // namespace vascsim::rod
