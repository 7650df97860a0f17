#pragma once
// The two records that cross between the haptic thread and the simulation thread (docs/haptics.md),
// each through its own LatestValue:
//   haptic -> simulation: ToolPose, the tool (proxy) pose at a haptic tick;
//   simulation -> haptic: ContactState, the contact result of one simulation step together with a
//   local linearisation, so the 1 kHz loop can extrapolate the force between the slower simulation
//   updates (docs/model/24-implicit.md section 24.3).
// Both are trivially copyable (plain arrays, not Eigen types, whose copies are user-defined) so the
// hand-off is a memcpy. Accessors convert to Eigen.

#include <array>
#include <cstdint>

#include "vascsim/core/types.hpp"

namespace vascsim {

/// The tool pose the haptic thread publishes for the simulation, once per tick.
struct ToolPose {
  std::uint64_t sequence = 0;  ///< 1, 2, ... per published pose; 0: nothing published yet
  double time_s = 0.0;         ///< haptic-clock time of the tick that produced it
  std::array<double, 3> position_m{};
  std::array<double, 4> orientation_wxyz{1.0, 0.0, 0.0, 0.0};  ///< unit quaternion, w first
  std::uint32_t buttons = 0;

  Vec3 position() const { return {position_m[0], position_m[1], position_m[2]}; }
  Eigen::Quaterniond orientation() const {
    return {orientation_wxyz[0], orientation_wxyz[1], orientation_wxyz[2], orientation_wxyz[3]};
  }
  void set_position(const Vec3& p) { position_m = {p.x(), p.y(), p.z()}; }
  void set_orientation(const Eigen::Quaterniond& q) { orientation_wxyz = {q.w(), q.x(), q.y(), q.z()}; }
};

/// What one simulation step publishes for the haptic thread.
///
/// Between two updates the haptic loop evaluates force_at(p) for the current tool position p:
///     F(p) = F_sim + K (p_sim - p),
/// then, if a contact normal n is given, drops an attractive normal component (n . F < 0): a one-sided
/// contact pushes but never pulls, so extrapolating past the point of separation gives zero normal force
/// instead of glue.
///
/// A model that knows the wall's compliance at the contacts (the implicit model, docs/haptics.md) also
/// publishes candidate contacts: the nodes in contact and those about to touch, each with its normal, its gap
/// and its normal force, and their contact-space compliance W. force_at then re-solves the small unilateral
/// problem at p (0 <= lambda, gap(lambda, p) >= 0, lambda gap = 0, with gap_c = g_c - n_c . dp +
/// sum_d W_cd (lambda_d - lambda*_d)) by projected Gauss-Seidel and adds what contacts opening or closing
/// change with respect to the held set that K describes.
struct ContactState {
  /// Most candidate contacts one state carries (the nearest to the tool first).
  static constexpr int kMaxCandidates = 24;
  std::uint64_t sequence = 0;  ///< 1, 2, ... per simulation step; 0: no state yet (force_at is zero)
  double sim_time_s = 0.0;     ///< simulation time of the step
  /// The tool pose the step used (copied from the ToolPose it read). Its time_s is on the haptic clock,
  /// so (tick time - tool.time_s) is the age of this force: the force latency.
  ToolPose tool;
  /// Force on the tool from the contact constraints, N (e.g. -sum lambda_c n_c / h^2,
  /// docs/model/19-position-based.md).
  std::array<double, 3> force_n{};
  /// dF/d(-p): contact stiffness, N/m, row-major 3x3, symmetric positive semi-definite. For one
  /// contact of stiffness k along the unit normal n: k n n^T (normal_stiffness()).
  std::array<double, 9> stiffness_n_per_m{};
  /// Unit contact normal, pointing from the tissue towards the tool (the direction the tissue pushes);
  /// zero when there is no single normal (then the extrapolation is not made one-sided).
  std::array<double, 3> normal{};
  /// Candidate contacts (0: none; force_at uses K alone). Per candidate c: the unit normal out of the tool
  /// into the tissue, its gap to the tool at p_sim (0 for a contact, m) and its normal force on the tissue
  /// (N).
  int candidates = 0;
  std::array<double, 3 * kMaxCandidates> candidate_normal{};
  std::array<double, kMaxCandidates> candidate_gap_m{};
  std::array<double, kMaxCandidates> candidate_force_n{};
  /// W_cd: the normal displacement at c per unit normal force at d, m/N, row-major kMaxCandidates^2.
  std::array<double, kMaxCandidates * kMaxCandidates> compliance_m_per_n{};

  Vec3 force() const { return {force_n[0], force_n[1], force_n[2]}; }
  Mat3 stiffness() const {
    Mat3 k;
    k << stiffness_n_per_m[0], stiffness_n_per_m[1], stiffness_n_per_m[2], stiffness_n_per_m[3],
        stiffness_n_per_m[4], stiffness_n_per_m[5], stiffness_n_per_m[6], stiffness_n_per_m[7],
        stiffness_n_per_m[8];
    return k;
  }
  Vec3 contact_normal() const { return {normal[0], normal[1], normal[2]}; }
  void set_force(const Vec3& f) { force_n = {f.x(), f.y(), f.z()}; }
  void set_stiffness(const Mat3& k) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) stiffness_n_per_m[static_cast<std::size_t>(3 * r + c)] = k(r, c);
  }
  void set_normal(const Vec3& n) { normal = {n.x(), n.y(), n.z()}; }

  /// The extrapolated force on the tool at position `p_m` (see above). Zero before the first state.
  /// `stiffness_scale` (in [0, 1]) lets a controller soften K (and the candidates' response) to what it can
  /// render stably.
  Vec3 force_at(const Vec3& p_m, double stiffness_scale = 1.0) const {
    if (sequence == 0) return Vec3::Zero();
    Vec3 f = force() + stiffness_scale * (stiffness() * (tool.position() - p_m));
    if (candidates > 0) f -= stiffness_scale * set_change_force(p_m - tool.position());
    const Vec3 n = contact_normal();
    const double fn = n.dot(f);
    if (fn < 0.0) f -= fn * n;  // n = 0 leaves f unchanged
    return f;
  }

  /// The change of the force on the tissue that contacts opening and closing add when the tool moves by dp
  /// from p_sim: (unilateral solution) - (the held set's linear solution), N. Both by Gauss-Seidel sweeps.
  Vec3 set_change_force(const Vec3& dp) const;

  void set_candidate(int c, const Vec3& normal_into_tissue, double gap_m, double force_n) {
    candidate_normal[static_cast<std::size_t>(3 * c)] = normal_into_tissue.x();
    candidate_normal[static_cast<std::size_t>(3 * c + 1)] = normal_into_tissue.y();
    candidate_normal[static_cast<std::size_t>(3 * c + 2)] = normal_into_tissue.z();
    candidate_gap_m[static_cast<std::size_t>(c)] = gap_m;
    candidate_force_n[static_cast<std::size_t>(c)] = force_n;
  }
  double& compliance(int c, int d) {
    return compliance_m_per_n[static_cast<std::size_t>(c * kMaxCandidates + d)];
  }
  double compliance(int c, int d) const {
    return compliance_m_per_n[static_cast<std::size_t>(c * kMaxCandidates + d)];
  }
};

/// k n n^T: the stiffness of one frictionless contact of stiffness `k_n_per_m` along the unit `normal`.
inline Mat3 normal_stiffness(const Vec3& normal, double k_n_per_m) {
  return k_n_per_m * normal * normal.transpose();
}

}  // namespace vascsim
