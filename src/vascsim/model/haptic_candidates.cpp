#include "vascsim/model/haptic_candidates.hpp"

#include <algorithm>

namespace vascsim {

bool HapticCandidates::fill(std::size_t tool, const ContactActiveSet& contacts, const Vec3Array& x,
                            const EquilibriumPreconditioner& preconditioner, NodeCompliance& compliance,
                            ToolLinearization& lin) {
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
  std::sort(touching.begin(), touching.end(),
            [](const Entry& a, const Entry& b) { return a.force > b.force; });
  std::sort(near.begin(), near.end(), [](const Entry& a, const Entry& b) { return a.gap < b.gap; });
  std::vector<Entry> chosen(touching.begin(),
                            touching.begin() + std::min<std::ptrdiff_t>(touching.size(), max_));
  for (const Entry& e : near) {
    if (static_cast<int>(chosen.size()) >= max_) break;
    chosen.push_back(e);
  }
  const auto m = static_cast<Eigen::Index>(chosen.size());
  lin.candidates.clear();
  lin.compliance_m_per_n.resize(m, m);
  if (m == 0) return true;
  std::vector<Index> nodes;
  for (const Entry& e : chosen) {
    nodes.push_back(e.node);
    lin.candidates.push_back({e.normal, e.gap, e.force});
  }
  if (!compliance.prepare(nodes, preconditioner)) {
    lin.candidates.clear();
    lin.compliance_m_per_n.resize(0, 0);
    return false;
  }
  // W_cd = n_c^T C_cd n_d with today's normals, symmetrised (C is symmetric up to the solve's round-off).
  for (Eigen::Index c = 0; c < m; ++c)
    for (Eigen::Index d = 0; d < m; ++d) {
      const Entry& a = chosen[static_cast<std::size_t>(c)];
      const Entry& b = chosen[static_cast<std::size_t>(d)];
      lin.compliance_m_per_n(c, d) = a.normal.dot(compliance.coupling(a.node, b.node) * b.normal);
    }
  lin.compliance_m_per_n = (0.5 * (lin.compliance_m_per_n + lin.compliance_m_per_n.transpose())).eval();
  return true;
}

}  // namespace vascsim
