#include "vascsim/model/contact_correction.hpp"

namespace vascsim {

bool ContactCorrection::update(const EquilibriumPreconditioner& preconditioner) {
  std::vector<Index> nodes;
  for (Index i : free_.nodes)
    if (contacts_.in_contact(i)) nodes.push_back(i);
  if (nodes.empty()) {
    valid_ = false;
    nodes_.clear();
    return false;
  }
  if (valid_ && nodes == nodes_ && version_ == preconditioner.version()) return true;
  const auto m = static_cast<Eigen::Index>(nodes.size());
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(free_.size(), m);
  Vec3Array normals(nodes.size());
  for (Eigen::Index c = 0; c < m; ++c) {
    const Index i = nodes[static_cast<std::size_t>(c)];
    normals[static_cast<std::size_t>(c)] = contacts_.normal(i);
    B.block<3, 1>(3 * static_cast<Eigen::Index>(free_.slot[static_cast<std::size_t>(i)]), c) = contacts_.normal(i);
  }
  if (!preconditioner.solve_columns(B, C_)) {
    valid_ = false;
    return false;
  }
  W_ = B.transpose() * C_;
  W_ldlt_.compute(W_);
  valid_ = W_ldlt_.info() == Eigen::Success;
  nodes_ = std::move(nodes);
  normals_ = std::move(normals);
  version_ = preconditioner.version();
  return valid_;
}

void ContactCorrection::apply(Vec3Array& z) const {
  if (!valid_) return;
  const auto m = static_cast<Eigen::Index>(nodes_.size());
  Eigen::VectorXd nz(m);
  for (Eigen::Index c = 0; c < m; ++c) nz[c] = normals_[static_cast<std::size_t>(c)].dot(z[nodes_[static_cast<std::size_t>(c)]]);
  const Eigen::VectorXd y = W_ldlt_.solve(nz);
  const Eigen::VectorXd dz = C_ * y;
  for (std::size_t a = 0; a < free_.nodes.size(); ++a) z[free_.nodes[a]] -= dz.segment<3>(3 * static_cast<Eigen::Index>(a));
}

}  // namespace vascsim
