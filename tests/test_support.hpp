#pragma once
// Shared fixtures of the unit tests: the MODEL.md section 6 node clouds, a tissue material, and a way
// to record measured values in the test report.

#include <gtest/gtest.h>

#include <cstdint>
#include <iomanip>
#include <sstream>
#include <string>

#include "vascsim/geometry/generators.hpp"
#include "vascsim/model/material.hpp"

namespace vascsim::test {

constexpr double kDelta = 1e-3;  // node spacing, m

/// Records a measured value in the test report (--gtest_output=xml), 6 significant digits.
inline void record(const std::string& key, double value) {
  std::ostringstream s;
  s << std::setprecision(6) << value;
  ::testing::Test::RecordProperty(key, s.str());
}

/// A cube of `cells`^3 lattice cells of edge kDelta, nodes jittered by `jitter` * kDelta (MODEL.md
/// section 6 default: 6 cells (7^3 nodes), jitter 0.2).
inline NodeCloud lattice(int cells, double jitter = 0.0, std::uint64_t seed = 1) {
  BoxSpec spec;
  spec.min_m = Vec3::Zero();
  spec.max_m = Vec3::Constant(cells * kDelta);
  spec.cells = Eigen::Vector3i::Constant(cells);
  spec.jitter = jitter;
  spec.seed = seed;
  return make_box(spec);
}

inline Material tissue(double youngs_modulus_pa, double poisson_ratio = 0.45) {
  Material m;
  m.youngs_modulus_pa = youngs_modulus_pa;
  m.poisson_ratio = poisson_ratio;
  m.density_kg_m3 = 1060.0;
  return m;
}

}  // namespace vascsim::test
