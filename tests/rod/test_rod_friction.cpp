// Coulomb friction between the rod and the lumen (docs/model/26-rod.md section 26.6): a straight wire lying
// on the floor of a tilted tube stays put below the critical angle atan(mu) and slides with the acceleration
// g (sin(theta) - mu cos(theta)) above it, stepped in time with the rod's inertia (backward Euler).

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "vascsim/rod/centerline_lumen.hpp"
#include "vascsim/rod/lumen_friction.hpp"
#include "vascsim/rod/rod_inertia.hpp"

namespace vascsim::rod {
namespace {

constexpr double kGravity = 9.81;                  // m/s^2
constexpr double kMu = 0.1;                        // a hydrophilic coating's order
constexpr double kStep = 1e-3;                     // s
constexpr double kSlip = 1e-8;                     // m, below which a node sticks
constexpr int kSteps = 100;                        // 0.1 s
constexpr double kFrictionWireR = 0.5 * 0.889e-3;  // m

// How far (m, along the tube's axis, downhill positive) a 20 mm wire lying on the floor of a 2 mm tube tilted
// by `theta` slides in kSteps steps.
double slid(double theta) {
  const CenterlineLumen lumen(straight_centerline(60e-3), 2e-3);  // along +z
  const double floor_y = -(2e-3 - kFrictionWireR);
  CosseratRod rod(straight_rod(Vec3(0, floor_y, 20e-3), Vec3::UnitZ(), Vec3::UnitX(), 20e-3, 20),
                  rod_stiffness(RodSection{2.0 * kFrictionWireR, 0.0, 60e9, 60e9 / 2.66}));
  const double rho_a =
      6450.0 * RodSection{2.0 * kFrictionWireR, 0.0, 60e9, 60e9 / 2.66}.area_m2();  // nitinol
  RodInertia inertia(rod, rho_a, kStep);
  LumenContact contact(lumen, kFrictionWireR, rod.stiffness().shear_stretch_n[2] / 1e-3);
  LumenFriction friction(kMu, kSlip);
  const std::vector<char> free(static_cast<std::size_t>(rod.num_dofs()), 0);
  // Gravity in the tube's frame: across it (-y) by cos(theta), along it (-z, downhill) by sin(theta).
  auto gravity = [&](double along) {
    Vec3Array f(static_cast<std::size_t>(rod.num_nodes()));
    for (std::size_t i = 0; i < f.size(); ++i)
      f[i] = inertia.masses()[i] * kGravity * Vec3(0, -std::cos(theta), -along * std::sin(theta));
    return f;
  };
  // Settled on the floor under the weight's normal part (the contact's normal forces for the friction).
  EXPECT_TRUE(solve_in_lumen(rod, free, gravity(0.0), contact, 1e-3 * kFrictionWireR).statics.converged);
  const double z0 = rod.positions().front().z();
  inertia.end_step(rod);  // at rest there
  for (int n = 0; n < kSteps; ++n) {
    friction.begin_step(rod, contact, lumen);
    inertia.begin_step();
    const LumenSolveReport r = solve_in_lumen(rod, free, gravity(1.0), contact, 1e-3 * kFrictionWireR, 10,
                                              {1, 100, 1e-6}, {&friction, &inertia});
    EXPECT_TRUE(r.statics.converged) << "step " << n << ": relative residual " << r.statics.relative_residual;
    inertia.end_step(rod);
  }
  return z0 - rod.positions().front().z();
}

TEST(RodFriction, AWireOnATiltedWallSticksBelowTheCriticalAngle) {
  // One degree below atan(mu): static friction holds. A node that sticks creeps by at most the slip per step.
  const double theta = std::atan(kMu) - std::numbers::pi / 180.0;
  EXPECT_LT(std::abs(slid(theta)), kSteps * kSlip);
}

TEST(RodFriction, AWireOnATiltedWallSlidesAboveTheCriticalAngleAtCoulombsAcceleration) {
  // One degree above atan(mu): a = g (sin - mu cos), 0.172 m/s^2; backward Euler from rest under a constant
  // acceleration moves a h^2 n (n + 1) / 2 in n steps (0.87 mm here). 1 %: the normal force is lagged a step
  // and the slip's spring holds the first e of it; both are far smaller.
  const double theta = std::atan(kMu) + std::numbers::pi / 180.0;
  const double a = kGravity * (std::sin(theta) - kMu * std::cos(theta));
  const double expected = a * kStep * kStep * kSteps * (kSteps + 1) / 2.0;
  EXPECT_NEAR(slid(theta) / expected, 1.0, 0.01);
}

}  // namespace
}  // namespace vascsim::rod
