// docs/validation.md (tests T1-T15), T1: kernel normalisation and shape (poly6 of Eq. 1, cubic spline of Eq.
// 37).

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "vascsim/core/kernels.hpp"

namespace {

namespace kernels = vascsim::kernels;

// Midpoint quadrature of a radial kernel W(r) over the cube [-h, h]^3 on a grid of spacing h/50
// (one octant, times 8, by symmetry).
double integrate_3d(const std::function<double(double)>& W, double h) {
  const int n = 50;
  const double dx = h / n;
  double sum = 0.0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const double x = (i + 0.5) * dx, y = (j + 0.5) * dx, z = (k + 0.5) * dx;
        sum += W(std::sqrt(x * x + y * y + z * z));
      }
  return 8.0 * sum * dx * dx * dx;
}

constexpr double kH = 2e-3;  // support radius, m (h = 2 Delta at Delta = 1 mm)

TEST(KernelT1, Poly6IntegratesToOne) {
  const double integral = integrate_3d([](double r) { return kernels::poly6(r, kH); }, kH);
  // Tolerance 1e-3 (docs/validation.md T1): midpoint error at h/50 is O(1e-4) at most. Measured 4.4e-10.
  EXPECT_NEAR(integral, 1.0, 1e-3);
}

TEST(KernelT1, CubicSpline3dIntegratesToOne) {
  const double integral = integrate_3d([](double r) { return kernels::cubic_spline_3d(r, kH); }, kH);
  // Same quadrature and tolerance as poly6 (the normalisation 12/pi is claimed exact). Measured 5.6e-10.
  EXPECT_NEAR(integral, 1.0, 1e-3);
}

TEST(KernelT1, VanishAtSupportAndNonNegative) {
  // W(h) = 0 exactly (both are polynomials with a root at the support), and zero beyond it.
  EXPECT_EQ(kernels::poly6(kH, kH), 0.0);
  EXPECT_EQ(kernels::cubic_spline_3d(kH, kH), 0.0);
  EXPECT_EQ(kernels::cubic_spline(1.0), 0.0);
  EXPECT_EQ(kernels::poly6(1.5 * kH, kH), 0.0);
  EXPECT_EQ(kernels::cubic_spline_3d(1.5 * kH, kH), 0.0);
  // W >= 0 on a fine sweep of [0, 1.2 h], and strictly positive inside the support.
  for (int s = 0; s <= 1200; ++s) {
    const double r = kH * s / 1000.0;
    const double w1 = kernels::poly6(r, kH), w2 = kernels::cubic_spline_3d(r, kH);
    ASSERT_GE(w1, 0.0) << "poly6 at r/h = " << r / kH;
    ASSERT_GE(w2, 0.0) << "cubic spline at r/h = " << r / kH;
    if (s < 1000) {
      ASSERT_GT(w1, 0.0) << "poly6 at r/h = " << r / kH;
      ASSERT_GT(w2, 0.0) << "cubic spline at r/h = " << r / kH;
    }
  }
}

TEST(KernelT1, CubicSplineIsC2AtOneHalf) {
  // One-sided differences from each side of s = 1/2 must agree in value, slope and curvature.
  auto W = [](double s) { return kernels::cubic_spline(s); };
  const double s0 = 0.5, d = 1e-4;
  const double left1 = (W(s0) - W(s0 - d)) / d, right1 = (W(s0 + d) - W(s0)) / d;
  const double left2 = (W(s0) - 2.0 * W(s0 - d) + W(s0 - 2.0 * d)) / (d * d);
  const double right2 = (W(s0 + 2.0 * d) - 2.0 * W(s0 + d) + W(s0)) / (d * d);
  // Value: both pieces give 1/6 at s = 1/2 (limit from the right taken at 1e-12).
  EXPECT_NEAR(W(s0 + 1e-12), W(s0), 1e-11);
  // Slope: one-sided differences carry an O(d W'') = 4e-4 truncation error each, so 2e-3.
  EXPECT_NEAR(left1, right1, 2e-3);
  EXPECT_NEAR(left1, -1.0, 2e-3);
  // Curvature: O(d W''') = 2.4e-3 truncation error each (W''' jumps from 24 to -8), so 1e-2.
  EXPECT_NEAR(left2, right2, 1e-2);
  EXPECT_NEAR(left2, 4.0, 1e-2);
  // The analytic derivative is continuous and matches central differences everywhere on [0, 1].
  EXPECT_NEAR(kernels::cubic_spline_derivative(s0 - 1e-12), kernels::cubic_spline_derivative(s0 + 1e-12),
              1e-10);
  for (int k = 1; k < 100; ++k) {
    const double s = k / 100.0 + 0.003, e = 1e-6;
    // Central difference error O(e^2 W''') ~ 1e-11 plus rounding 1e-16/e ~ 1e-10.
    EXPECT_NEAR(kernels::cubic_spline_derivative(s), (W(s + e) - W(s - e)) / (2.0 * e), 1e-8) << "s = " << s;
  }
}

}  // namespace
