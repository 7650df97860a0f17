// Richardson extrapolation with the observed order (core/richardson.hpp): exact on a sequence that is exactly
// f0 + C h^p, Celik et al. 2008's own worked example to its printed digits, and the sequences it must refuse.

#include <gtest/gtest.h>

#include <cmath>

#include "vascsim/core/richardson.hpp"

namespace vascsim {
namespace {

// f = f0 + C h^p on unequal ratios (r21 = 1.5, r32 = 1.6; h in mm, differences of 1e-4 to 1e-2 of f0): the
// fixed-point iteration for p must recover p and f0 to rounding (1e-8 relative: the iteration stops at 1e-12
// in p, and the differences carry about 1e-12 of relative rounding).
TEST(Richardson, RecoversTheOrderAndTheLimitOfAnExactPowerLaw) {
  for (double p : {1.0, 1.7, 2.0, 3.0}) {
    const double f0 = 0.0101, c = 1e-3, h[3] = {0.15, 0.225, 0.36};
    const double f[3] = {f0 + c * std::pow(h[0], p), f0 + c * std::pow(h[1], p), f0 + c * std::pow(h[2], p)};
    const Richardson r = richardson_extrapolate(h, f);
    ASSERT_EQ(r.status, RichardsonStatus::Extrapolated) << p;
    EXPECT_NEAR(r.order, p, 1e-8 * p) << p;
    EXPECT_NEAR(r.extrapolated, f0, 1e-9 * f0) << p;
    EXPECT_NEAR(r.fine_error, (f[0] - f0) / f0, 1e-7) << p;
    // The GCI bound is the factor of safety times the distance to the limit, relative to f1.
    EXPECT_NEAR(r.fine_gci, kGciSafetyFactor * std::abs(f[0] - f0) / f[0], 1e-7) << p;
    EXPECT_NEAR(resolution_for_error(h[0], r.fine_error, r.order, 0.5 * r.fine_error),
                h[0] * std::pow(0.5, 1.0 / p), 1e-9);
  }
}

// Celik et al. 2008, Table 1 (their first example: N = 18000, 8000, 4500 cells in 2-D, so r21 = 1.5, r32 =
// 4/3): phi = 6.063, 5.972, 5.863 give p = 1.53, phi_ext = 6.1685, e_ext = 1.7 %, GCI_fine = 2.2 %.
// Tolerances are half a unit of the digits they print.
TEST(Richardson, ReproducesCeliksWorkedExample) {
  const double h[3] = {1.0, 1.5, 2.0}, f[3] = {6.063, 5.972, 5.863};
  const Richardson r = richardson_extrapolate(h, f);
  ASSERT_EQ(r.status, RichardsonStatus::Extrapolated);
  EXPECT_NEAR(r.order, 1.53, 0.005);
  EXPECT_NEAR(r.extrapolated, 6.1685, 0.00005);
  EXPECT_NEAR(std::abs(r.fine_error), 0.017, 0.0005);
  EXPECT_NEAR(r.fine_gci, 0.022, 0.0005);
}

TEST(Richardson, RefusesSequencesOutsideTheAsymptoticRange) {
  const double h[3] = {1.0, 1.41, 2.0};
  {  // up and down
    const double f[3] = {1.007, 0.981, 1.064};
    const Richardson r = richardson_extrapolate(h, f);
    EXPECT_EQ(r.status, RichardsonStatus::Oscillating);
    EXPECT_EQ(r.fine_gci, 0.0);
  }
  {  // differences that barely shrink: p = ln(1.05) / ln(1.41), about 0.14
    const double f[3] = {1.0, 1.1, 1.205};
    const Richardson r = richardson_extrapolate(h, f);
    EXPECT_EQ(r.status, RichardsonStatus::OrderOutOfRange);
    EXPECT_LT(r.order, kMinObservedOrder);
  }
  {  // differences that grow towards the fine end (the vein's catheter at 0.9 mm, 0.15 / 0.21 / 0.30 mm):
     // diverging, whatever |ln| in Celik's formula would make of it
    const double f[3] = {8.1005, 8.0477, 8.0373};
    const Richardson r = richardson_extrapolate(h, f);
    EXPECT_EQ(r.status, RichardsonStatus::OrderOutOfRange);
    EXPECT_LT(r.order, 0.0);
  }
  {  // the same value at every resolution
    const double f[3] = {2.5, 2.5, 2.5};
    EXPECT_EQ(richardson_extrapolate(h, f).status, RichardsonStatus::Exact);
  }
  EXPECT_STREQ(richardson_status_name(RichardsonStatus::Oscillating), "oscillating");
}

}  // namespace
}  // namespace vascsim
