#pragma once
// The rod inside a rigid lumen (docs/model/26-rod.md section 26.4): every free node of the rod stays within
// the lumen's radius less the rod's own. Frictionless, by an augmented Lagrangian: the energy
//     E_c = sum_i 1/(2k) [max(0, lambda_i + k g_i)^2 - lambda_i^2],   g_i = d_i - (R_i - r)   (m)
// with d_i the node's distance from the lumen's axis, R_i the lumen's radius there and r the rod's radius
// (g > 0: the rod's surface is beyond the lumen's wall); after each equilibrium the multipliers take the
// contact forces, lambda_i <- max(0, lambda_i + k g_i), and the solve is repeated until no node is beyond the
// wall by more than the tolerance. The penalty k defaults to the edges' axial stiffness EA / l: as stiff as
// the rod itself, so it does not worsen the Hessian's conditioning.

#include <memory>

#include "vascsim/rod/rod_potential.hpp"
#include "vascsim/rod/rod_statics.hpp"

namespace vascsim::rod {

/// Where a point is in a lumen: its distance from the lumen's axis (m), the outward radial direction (unit,
/// across the axis), the axis's direction there (unit) and the lumen's radius there (m).
struct LumenPoint {
  double distance_m = 0.0;
  Vec3 outward = Vec3::UnitX();
  Vec3 axis = Vec3::UnitZ();
  double radius_m = 0.0;
};

class Lumen {
 public:
  virtual ~Lumen() = default;
  virtual LumenPoint at(const Vec3& x) const = 0;
};

class LumenContact final : public RodPotential {
 public:
  /// Contact of `rod`'s nodes (rod radius `rod_radius_m`) with `lumen`, which must outlive this. Nodes
  /// flagged in `exempt` (one flag per node; empty: none) are not checked: the part of the rod outside the
  /// body.
  LumenContact(const Lumen& lumen, double rod_radius_m, double penalty_n_per_m);

  void set_exempt(std::vector<char> exempt) { exempt_ = std::move(exempt); }
  double energy(const CosseratRod& rod) const override;
  void add_gradient(const CosseratRod& rod, Eigen::VectorXd& g) const override;
  void add_hessian(const CosseratRod& rod, std::vector<Eigen::Triplet<double>>& t) const override;

  /// The augmented Lagrangian's update at an equilibrium: every multiplier takes its node's contact force
  /// (N).
  void update_multipliers(const CosseratRod& rod);
  /// The largest distance a checked node's surface is beyond the lumen's wall (m; <= 0: none is).
  double max_penetration(const CosseratRod& rod) const;
  /// Each node's contact force on the rod, pointing into the lumen (N; zero where there is no contact).
  Vec3Array forces(const CosseratRod& rod) const;
  const std::vector<double>& multipliers() const { return lambda_; }

 private:
  bool checked(Index i) const { return exempt_.empty() || !exempt_[static_cast<std::size_t>(i)]; }
  double gap(const LumenPoint& p) const { return p.distance_m - (p.radius_m - r_); }

  const Lumen& lumen_;
  double r_ = 0.0, k_ = 0.0, w_ = 0.0;  // w_: the penalty's smoothing width, a hundredth of the rod's radius
  mutable std::vector<double> lambda_;
  std::vector<char> exempt_;
};

/// How far the rod's surface goes beyond the lumen's wall at most, m (<= 0: nowhere; -infinity when every
/// node is outside the body): checked at the nodes and at the edges' midpoints, where a straight edge across
/// a bend cuts the corner that the nodes alone would miss. Nodes flagged in `outside` (one flag per node: the
/// part of the rod before the access port) and the edges touching them are skipped.
double worst_outside(const CosseratRod& rod, const std::vector<char>& outside, const Lumen& lumen,
                     double rod_radius_m);

struct LumenSolveReport {
  RodStaticsReport statics;      ///< of the last pass (its Newton iterations: of all passes)
  int passes = 0;                ///< equilibria solved (multiplier updates + 1)
  double max_penetration_m = 0;  ///< after the last pass (<= 0: no node beyond the wall)
};

/// The rod's equilibrium inside the lumen: solve_rod_statics with `contact`, then multiplier updates and
/// solves again until no checked node is beyond the wall by more than `tolerance_m`, at most `max_passes`
/// solves, with the energies `others` (friction, inertia) beside the contact. The multipliers carry over to
/// the next call (a warm start for the next frame). The default tolerance is 10^-6, not the free rod's
/// 10^-10: a frictionless rod against a straight stretch of wall may roll round it at no cost (a singular
/// Hessian), and Newton converges only linearly there (a wire in the aorta's arch took over 100 steps from
/// 10^-6 to 10^-10; 10^-6 of the contact forces is micro- to nano-newtons).
LumenSolveReport solve_in_lumen(CosseratRod& rod, const std::vector<char>& held, const Vec3Array& forces,
                                LumenContact& contact, double tolerance_m, int max_passes = 10,
                                const RodStaticsOptions& options = {1, 100, 1e-6},
                                const std::vector<const RodPotential*>& others = {});

}  // namespace vascsim::rod
