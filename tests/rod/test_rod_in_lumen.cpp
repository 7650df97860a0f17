// A guidewire fed through a rigid lumen (docs/model/26-rod.md sections 26.4-26.5): it never leaves the lumen
// at a hand's speed, and turning its proximal end steers its shaped tip.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "vascsim/rod/centerline_lumen.hpp"
#include "vascsim/rod/lumen_contact.hpp"
#include "vascsim/rod/rod_feeder.hpp"

namespace vascsim::rod {
namespace {

constexpr double kWireRadius = 0.5 * 0.889e-3;  // m, a 0.035-inch wire

RodSection lumen_wire() {
  return RodSection{2.0 * kWireRadius, 0.0, 60e9, 60e9 / (2.0 * 1.33)};
}

// A J-tipped wire (3 mm radius over 180 degrees) of `length_m` in 1 mm edges.
CosseratRod j_wire(double length_m) {
  return CosseratRod(shaped_tip_rod(Vec3::Zero(), Vec3::UnitZ(), Vec3::UnitX(), length_m,
                                    static_cast<int>(std::lround(length_m / 1e-3)), 3e-3, std::numbers::pi),
                     rod_stiffness(lumen_wire()));
}

TEST(RodInLumen, AWireFedIntoTheBentAortasArchAt20MmPerSecondNeverLeavesTheLumen) {
  // The bundled bent aorta's lumen (scenes/aorta-bent.json: 30 mm bend radius, 180 degrees, 10 mm legs, inner
  // radius 12.5 - 1.5 mm), entered at its start; the wire fed from 10 mm to 125 mm at 20 mm/s in frames of 10
  // ms (0.2 mm each), through the whole arch.
  const CenterlineLumen lumen(bent_centerline(30e-3, 180.0, 10e-3), 11e-3);
  const Centerline& c = lumen.centerline();
  CosseratRod rod = j_wire(0.16);
  RodFeeder feeder(rod, AccessPort{c.position(0.0), c.tangent(0.0)}, 10e-3);
  const double k = rod.stiffness().shear_stretch_n[2] / 1e-3;  // EA / l
  LumenContact contact(lumen, kWireRadius, k);
  const double step = 20e-3 * 0.01;
  int frames = 0;
  double worst = -1.0;
  for (double inserted = 10e-3 + step; inserted <= 80e-3 + 1e-12; inserted += step, ++frames) {
    feeder.drive(inserted, 0.0);
    contact.set_exempt(feeder.outside());
    const LumenSolveReport r = solve_in_lumen(rod, feeder.held(), {}, contact, 0.01 * kWireRadius);
    ASSERT_TRUE(r.statics.converged) << "frame " << frames << ", " << inserted * 1e3
                                     << " mm inserted: relative residual " << r.statics.relative_residual
                                     << " after " << r.statics.newton_iterations
                                     << " Newton steps, the tip at s = "
                                     << c.closest_arc_length(rod.positions().back()) * 1e3 << " mm";
    worst = std::max(worst, worst_outside(rod, feeder.outside(), lumen, kWireRadius));
    // The bound: no point of the rod farther outside the lumen than a tenth of its radius, at every
    // frame.
    ASSERT_LT(worst, 0.1 * kWireRadius) << "frame " << frames << ", " << inserted * 1e3 << " mm inserted";
  }
  EXPECT_EQ(frames, 350);
  // The tip went past the arch's apex: its nearest centre-line point is beyond 10 mm + 30 pi / 2 mm.
  EXPECT_GT(c.closest_arc_length(rod.positions().back()), 10e-3 + 0.5 * 30e-3 * std::numbers::pi);
}

TEST(RodInLumen, TurningTheProximalEndTurnsTheJTip) {
  // A straight lumen, the J tip free in it: turning the hands by 90 degrees turns the tip's hook by as much
  // (the wire is torsionally stiff and nothing holds the tip).
  const CenterlineLumen lumen(straight_centerline(60e-3), 1.5e-3 + 3e-3 * 2.0);
  const Centerline& c = lumen.centerline();
  CosseratRod rod = j_wire(0.06);
  RodFeeder feeder(rod, AccessPort{c.position(0.0), c.tangent(0.0)}, 30e-3);
  LumenContact contact(lumen, kWireRadius, rod.stiffness().shear_stretch_n[2] / 1e-3);
  auto hook = [&] {  // the tip's offset across the axis
    const Vec3 v = rod.positions().back() - c.position(c.closest_arc_length(rod.positions().back()));
    return Vec3(v - v.dot(c.tangent(0.0)) * c.tangent(0.0));
  };
  contact.set_exempt(feeder.outside());
  ASSERT_TRUE(solve_in_lumen(rod, feeder.held(), {}, contact, 0.01 * kWireRadius).statics.converged);
  const Vec3 before = hook();
  for (int k = 1; k <= 9; ++k) {  // in steps of 10 degrees
    feeder.drive(30e-3, k * std::numbers::pi / 18.0);
    ASSERT_TRUE(solve_in_lumen(rod, feeder.held(), {}, contact, 0.01 * kWireRadius).statics.converged);
  }
  const Vec3 after = hook();
  const double turned =
      std::atan2(before.cross(after).dot(c.tangent(0.0)), before.dot(after)) * 180.0 / std::numbers::pi;
  // The hook's size is kept and it turned by the hands' 90 degrees: a free tip in a straight lumen has no
  // reason to lag, so 1 degree is the rod's own round-off and discretisation, not a physical allowance.
  EXPECT_NEAR(after.norm(), before.norm(), 1e-3 * before.norm());
  EXPECT_NEAR(turned, 90.0, 1.0);
}

}  // namespace
}  // namespace vascsim::rod

namespace vascsim::rod {
namespace {

TEST(RodInLumen, TheContactForceIsTheDerivativeOfTheContactEnergy) {
  // A wire across the bent aorta's lumen near its outer wall, every node pressed 0 to 50 um beyond the wall
  // (past the penalty's smoothing width, 4.4 um, for most): the contact's gradient against central
  // differences of its energy, and its Hessian against those of the gradient.
  const CenterlineLumen lumen(bent_centerline(30e-3, 180.0, 10e-3), 11e-3);
  const Centerline& c = lumen.centerline();
  CosseratRod rod = j_wire(0.03);
  Vec3Array x = rod.positions();
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double s = 30e-3 + 1e-3 * static_cast<double>(i);  // round the bend
    const Frame f = c.frame(s);
    const double beyond = 50e-6 * static_cast<double>(i % 5) / 4.0;
    x[i] = f.T * 0.0 + c.position(s) + (11e-3 - kWireRadius + beyond) * (0.6 * f.N + 0.8 * f.B);
  }
  rod.set_configuration(x, rod.frames());
  LumenContact contact(lumen, kWireRadius, rod.stiffness().shear_stretch_n[2] / 1e-3);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(rod.num_dofs());
  contact.add_gradient(rod, g);
  std::vector<Eigen::Triplet<double>> t;
  contact.add_hessian(rod, t);
  Eigen::SparseMatrix<double> Hs(rod.num_dofs(), rod.num_dofs());
  Hs.setFromTriplets(t.begin(), t.end());
  const Eigen::MatrixXd H(Hs);
  const double h = 1e-9;  // m: a fifth of a thousandth of the smoothing width
  for (Index k = 0; k < 3 * rod.num_nodes(); ++k) {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(rod.num_dofs());
    d[k] = h;
    CosseratRod plus = rod, minus = rod;
    plus.apply_increment(d);
    minus.apply_increment(d, -1.0);
    // Energies of ~0.05 J differenced over 2e-9 m: round-off ~1e-8 N against forces of up to 2,000 N (50 um
    // beyond the wall at the penalty EA / l); 1e-8 of the largest force catches any inconsistent term.
    EXPECT_NEAR(g[k], (contact.energy(plus) - contact.energy(minus)) / (2.0 * h),
                1e-8 * g.cwiseAbs().maxCoeff())
        << "coordinate " << k;
    Eigen::VectorXd gp = Eigen::VectorXd::Zero(rod.num_dofs()), gm = gp;
    contact.add_gradient(plus, gp);
    contact.add_gradient(minus, gm);
    for (Index r = 0; r < 3 * rod.num_nodes(); ++r)  // 1e-6 of the penalty (N/m)
      EXPECT_NEAR(H(r, k), (gp[r] - gm[r]) / (2.0 * h), 1e-6 * rod.stiffness().shear_stretch_n[2] / 1e-3)
          << "entry (" << r << ", " << k << ")";
  }
}

}  // namespace
}  // namespace vascsim::rod
