#include "vascsim/model/haptic_candidates.hpp"

#include <algorithm>

namespace vascsim {

bool HapticCandidates::fill(std::size_t tool, const ContactActiveSet& contacts, const Vec3Array& x,
                            const EquilibriumPreconditioner& preconditioner, ToolLinearization& lin) {
  if (cache_.size() <= tool) cache_.resize(tool + 1);
  // In contact first (largest force first), then the open nodes by gap.
  struct Entry {
    Index node;
    Vec3 normal;
    double gap, force;
  };
  std::vector<Entry> touching, near;
  const constraints::Capsule& g = contacts.geometry(tool);
  for (Index i : free_.nodes) {
    if (contacts.in_contact(i)) {
      if (contacts.tool_of(i) == static_cast<int>(tool))
        touching.push_back({i, contacts.normal(i), 0.0, std::max(contacts.lambda(i), 0.0)});
      continue;
    }
    const auto c = obstacle_contact(g, x[static_cast<std::size_t>(i)]);
    if (c.value > 0.0 && c.value <= reach_) near.push_back({i, c.normal, c.value, 0.0});
  }
  std::sort(touching.begin(), touching.end(), [](const Entry& a, const Entry& b) { return a.force > b.force; });
  std::sort(near.begin(), near.end(), [](const Entry& a, const Entry& b) { return a.gap < b.gap; });
  std::vector<Entry> chosen(touching.begin(), touching.begin() + std::min<std::ptrdiff_t>(touching.size(), max_));
  for (const Entry& e : near) {
    if (static_cast<int>(chosen.size()) >= max_) break;
    chosen.push_back(e);
  }
  const auto m = static_cast<Eigen::Index>(chosen.size());
  lin.candidates.clear();
  lin.compliance_m_per_n.resize(m, m);
  if (m == 0) return true;
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(free_.size(), m);
  std::vector<Index> nodes;
  for (Eigen::Index c = 0; c < m; ++c) {
    const Entry& e = chosen[static_cast<std::size_t>(c)];
    nodes.push_back(e.node);
    N.block<3, 1>(3 * static_cast<Eigen::Index>(free_.slot[static_cast<std::size_t>(e.node)]), c) = e.normal;
    lin.candidates.push_back({e.normal, e.gap, e.force});
  }
  Cache& cache = cache_[tool];
  if (nodes != cache.nodes || cache.version != preconditioner.version()) {
    if (!preconditioner.solve_columns(N, cache.Z)) return false;
    cache.nodes = nodes;
    cache.version = preconditioner.version();
  }
  // The normals turn a little as nodes slide: W with today's normals and the cached P^{-1} N^T columns of the
  // normals at the build (exact when they agree, a small error otherwise).
  const Eigen::MatrixXd W = N.transpose() * cache.Z;
  lin.compliance_m_per_n = 0.5 * (W + W.transpose());
  return true;
}

}  // namespace vascsim
