#include "vascsim/interaction/contact_state.hpp"

#include <algorithm>

namespace vascsim {

Vec3 ContactState::set_change_force(const Vec3& dp) const {
  // Projected Gauss-Seidel on the candidates' linear complementarity problem (docs/haptics.md, "Candidate
  // contacts"), and plain Gauss-Seidel on the held set (the contacts with a gap of zero keep touching, the
  // others stay open): W is symmetric positive definite, so both converge; 40 sweeps of at most 24 unknowns
  // are about 50 k flops a tick. Allocation-free: the haptic thread calls this every tick.
  constexpr int kSweeps = 40;
  const int m = std::clamp(candidates, 0, kMaxCandidates);
  std::array<double, kMaxCandidates> lcp{}, held{}, ndp{};
  for (int c = 0; c < m; ++c) {
    const auto i = static_cast<std::size_t>(c);
    lcp[i] = held[i] = candidate_force_n[i];
    ndp[i] = candidate_normal[3 * i] * dp.x() + candidate_normal[3 * i + 1] * dp.y() +
             candidate_normal[3 * i + 2] * dp.z();
  }
  for (int sweep = 0; sweep < kSweeps; ++sweep)
    for (int c = 0; c < m; ++c) {
      const auto i = static_cast<std::size_t>(c);
      const double w = compliance(c, c);
      if (!(w > 0.0)) continue;
      double g_lcp = candidate_gap_m[i] - ndp[i], g_held = -ndp[i];
      for (int d = 0; d < m; ++d) {
        const auto j = static_cast<std::size_t>(d);
        g_lcp += compliance(c, d) * (lcp[j] - candidate_force_n[j]);
        g_held += compliance(c, d) * (held[j] - candidate_force_n[j]);
      }
      lcp[i] = std::max(0.0, lcp[i] - g_lcp / w);
      if (candidate_gap_m[i] == 0.0) held[i] -= g_held / w;
    }
  Vec3 df = Vec3::Zero();
  for (int c = 0; c < m; ++c) {
    const auto i = static_cast<std::size_t>(c);
    const Vec3 n(candidate_normal[3 * i], candidate_normal[3 * i + 1], candidate_normal[3 * i + 2]);
    df += (lcp[i] - held[i]) * n;
  }
  return df;
}

}  // namespace vascsim
