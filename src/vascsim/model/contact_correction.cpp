#include "vascsim/model/contact_correction.hpp"

#include <Eigen/LU>

namespace vascsim {

bool ContactCorrection::update(const EquilibriumPreconditioner& preconditioner, NodeCompliance& compliance) {
  std::vector<Index> nodes;
  for (Index i : free_.nodes)
    if (contacts_.in_contact(i)) nodes.push_back(i);
  const auto m = static_cast<Eigen::Index>(nodes.size());
  if (m == 0) {
    valid_ = false;
    nodes_.clear();
    return false;
  }
  if (!(nodes == nodes_ && version_ == preconditioner.version() && Z_.cols() == 3 * m)) {
    if (!compliance.prepare(nodes, preconditioner)) {
      valid_ = false;
      return false;
    }
    Z_.resize(free_.size(), 3 * m);
    C_.resize(3 * m, 3 * m);
    for (Eigen::Index d = 0; d < m; ++d) {
      const Index node = nodes[static_cast<std::size_t>(d)];
      Z_.middleCols<3>(3 * d) = compliance.columns(node);
      for (Eigen::Index c = 0; c < m; ++c)
        C_.block<3, 3>(3 * c, 3 * d) = compliance.coupling(nodes[static_cast<std::size_t>(c)], node);
    }
    C_ = (0.5 * (C_ + C_.transpose())).eval();
    nodes_ = std::move(nodes);
    version_ = preconditioner.version();
  }
  Nb_ = Eigen::MatrixXd::Zero(m, 3 * m);
  for (Eigen::Index c = 0; c < m; ++c)
    Nb_.block<1, 3>(c, 3 * c) = contacts_.normal(nodes_[static_cast<std::size_t>(c)]).transpose();
  W_ = Nb_ * C_ * Nb_.transpose();
  W_ldlt_.compute(W_);
  valid_ = W_ldlt_.info() == Eigen::Success;
  return valid_;
}

void ContactCorrection::apply(Vec3Array& z) const {
  if (!valid_) return;
  const auto m = static_cast<Eigen::Index>(nodes_.size());
  Eigen::VectorXd nz(m);
  for (Eigen::Index c = 0; c < m; ++c)
    nz[c] = contacts_.normal(nodes_[static_cast<std::size_t>(c)]).dot(z[nodes_[static_cast<std::size_t>(c)]]);
  const Eigen::VectorXd dz = Z_ * (Nb_.transpose() * W_ldlt_.solve(nz));
  for (std::size_t a = 0; a < free_.nodes.size(); ++a)
    z[free_.nodes[a]] -= dz.segment<3>(3 * static_cast<Eigen::Index>(a));
}

Mat3 ContactCorrection::curvature(Index node, const Vec3& x) const {
  const constraints::Capsule& g = contacts_.geometry(static_cast<std::size_t>(contacts_.tool_of(node)));
  const Vec3 n = contacts_.normal(node);
  Mat3 H = Mat3::Identity() - n * n.transpose();
  const Vec3 ab = g.b - g.a;
  const double len2 = ab.squaredNorm();
  // On the cylindrical part the surface does not curve along the axis e (same rule as the Newton matrix's
  // curvature term, ContactActiveSet::add_curvature): the node projects strictly inside the segment.
  if (len2 > 0.0) {
    const double u = (x - g.a).dot(ab) / len2;
    if (u > 0.0 && u < 1.0) {
      const Vec3 e = ab / std::sqrt(len2);
      H -= e * e.transpose();
    }
  }
  return H / g.radius_m;
}

Mat3 ContactCorrection::tool_stiffness(const std::vector<char>& mask, const Vec3Array& x) const {
  // Unknowns: the contact nodes' displacements u (3m) and normal force changes dl (m), for a tool translation
  // dp. The only loads that change are the contact forces, g_c = dl_c n_c + lambda_c H_c (u_c - dp) on the
  // masked contacts (the others keep their normal, g_c = dl_c n_c, and do not move with the tool), so u = C
  // g; the masked contacts follow the tool in their normal direction, n_c . u_c = n_c . dp, the others stay
  // shut, n_c . u_c = 0. The force change is sum_c g_c over the masked contacts, for dp = e_x, e_y, e_z.
  if (!valid_) return Mat3::Zero();
  const auto m = static_cast<Eigen::Index>(nodes_.size());
  Eigen::MatrixXd LH = Eigen::MatrixXd::Zero(3 * m, 3 * m), D = Eigen::MatrixXd::Zero(3 * m, 3);
  for (Eigen::Index c = 0; c < m; ++c) {
    const Index node = nodes_[static_cast<std::size_t>(c)];
    if (!mask[static_cast<std::size_t>(c)]) continue;
    LH.block<3, 3>(3 * c, 3 * c) =
        contacts_.lambda(node) * curvature(node, x[static_cast<std::size_t>(node)]);
    D.block<3, 3>(3 * c, 0) = Mat3::Identity();
  }
  // [I - C LH, -C Nb^T] [u ]   [-C LH D]
  // [Nb,        0    ] [dl] = [Nb D  ] dp      (Nb D dp = n_c . dp for masked contacts, 0 for the others)
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(4 * m, 4 * m), rhs(4 * m, 3);
  A.topLeftCorner(3 * m, 3 * m) = Eigen::MatrixXd::Identity(3 * m, 3 * m) - C_ * LH;
  A.topRightCorner(3 * m, m) = -C_ * Nb_.transpose();
  A.bottomLeftCorner(m, 3 * m) = Nb_;
  rhs.topRows(3 * m) = -C_ * LH * D;
  rhs.bottomRows(m) = Nb_ * D;
  const Eigen::MatrixXd sol = A.partialPivLu().solve(rhs);
  Mat3 K = Mat3::Zero();
  for (Eigen::Index c = 0; c < m; ++c) {
    if (!mask[static_cast<std::size_t>(c)]) continue;
    const Index node = nodes_[static_cast<std::size_t>(c)];
    const Vec3 n = contacts_.normal(node);
    for (int k = 0; k < 3; ++k) {
      const Vec3 u = sol.block<3, 1>(3 * c, k);
      Vec3 dp = Vec3::Zero();
      dp[k] = 1.0;
      K.col(k) += sol(3 * m + c, k) * n + LH.block<3, 3>(3 * c, 3 * c) * (u - dp);
    }
  }
  return K;
}

}  // namespace vascsim
