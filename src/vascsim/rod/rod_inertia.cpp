#include "vascsim/rod/rod_inertia.hpp"

#include <fmt/format.h>
#include <cmath>

#include "vascsim/core/error.hpp"

namespace vascsim::rod {

RodInertia::RodInertia(const CosseratRod& rod, double linear_density_kg_per_m, double step_s) : h_(step_s) {
  if (!(linear_density_kg_per_m > 0.0) || !std::isfinite(linear_density_kg_per_m) || !(step_s > 0.0) ||
      !std::isfinite(step_s))
    throw InputError(fmt::format("rod: linear density {} kg/m and step {} s must be positive",
                                 linear_density_kg_per_m, step_s));
  const Vec3Array& rest = rod.rest_shape().nodes;
  m_.assign(rest.size(), 0.0);
  for (std::size_t j = 0; j + 1 < rest.size(); ++j) {
    const double half = 0.5 * linear_density_kg_per_m * (rest[j + 1] - rest[j]).norm();
    m_[j] += half;
    m_[j + 1] += half;
  }
  x_n_ = rod.positions();
  v_.assign(x_n_.size(), Vec3::Zero());
  pred_ = x_n_;
}

void RodInertia::begin_step() {
  for (std::size_t i = 0; i < x_n_.size(); ++i) pred_[i] = x_n_[i] + h_ * v_[i];
}

void RodInertia::end_step(const CosseratRod& rod) {
  for (std::size_t i = 0; i < x_n_.size(); ++i) {
    v_[i] = (rod.positions()[i] - x_n_[i]) / h_;
    x_n_[i] = rod.positions()[i];
  }
}

double RodInertia::energy(const CosseratRod& rod) const {
  double e = 0.0;
  for (std::size_t i = 0; i < m_.size(); ++i)
    e += 0.5 * m_[i] / (h_ * h_) * (rod.positions()[i] - pred_[i]).squaredNorm();
  return e;
}

void RodInertia::add_gradient(const CosseratRod& rod, Eigen::VectorXd& g) const {
  for (std::size_t i = 0; i < m_.size(); ++i)
    g.segment<3>(CosseratRod::position_dof(static_cast<Index>(i))) +=
        m_[i] / (h_ * h_) * (rod.positions()[i] - pred_[i]);
}

void RodInertia::add_hessian(const CosseratRod& rod, std::vector<Eigen::Triplet<double>>& t) const {
  (void)rod;
  for (std::size_t i = 0; i < m_.size(); ++i)
    for (int a = 0; a < 3; ++a) {
      const Index d = CosseratRod::position_dof(static_cast<Index>(i)) + a;
      t.emplace_back(d, d, m_[i] / (h_ * h_));
    }
}

}  // namespace vascsim::rod
