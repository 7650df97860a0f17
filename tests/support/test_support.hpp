#pragma once
// Shared fixtures of the unit tests: the docs/validation.md (tests T1-T15) node clouds, a tissue material,
// and a way to record measured values in the test report.

#include <gtest/gtest.h>

#include <cstdint>
#include <iomanip>
#include <sstream>
#include <string>

#include <omp.h>

#include <span>

#include "vascsim/constraints/meshless_strain_constraint.hpp"
#include "vascsim/geometry/generators.hpp"
#include "vascsim/model/discretization.hpp"
#include "vascsim/model/material.hpp"

namespace vascsim::test {

constexpr double kDelta = 1e-3;  // node spacing, m

/// Records a measured value in the test report (--gtest_output=xml), 6 significant digits.
inline void record(const std::string& key, double value) {
  std::ostringstream s;
  s << std::setprecision(6) << value;
  ::testing::Test::RecordProperty(key, s.str());
}

/// A cube of `cells`^3 lattice cells of edge kDelta, nodes jittered by `jitter` * kDelta (the T1-T10 default
/// of docs/validation.md: 6 cells (7^3 nodes), jitter 0.2).
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

/// Runs the enclosing test on one OpenMP thread (bitwise comparisons, tiny clouds), restoring the count.
class SingleThreaded {
 public:
  SingleThreaded() : saved_(omp_get_max_threads()) { omp_set_num_threads(1); }
  ~SingleThreaded() { omp_set_num_threads(saved_); }
  SingleThreaded(const SingleThreaded&) = delete;
  SingleThreaded& operator=(const SingleThreaded&) = delete;

 private:
  int saved_;
};

}  // namespace vascsim::test

namespace vascsim::constraints {

/// The strain constraint of node i reading row i of disc.pairs() and disc.self_d()[i] (tests only: the
/// library's kernel takes the row itself, so constraints/ does not depend on model/).
inline void meshless_strain_constraint(const Discretization& disc, Index i, const Vec3Array& x,
                                       MeshlessStrainEval& out) {
  const PairTable& pairs = disc.pairs();
  const auto begin = static_cast<std::size_t>(pairs.row_start[static_cast<std::size_t>(i)]);
  const auto size = static_cast<std::size_t>(pairs.row_size(i));
  meshless_strain_constraint(i, std::span<const Index>(pairs.col.data() + begin, size),
                             std::span<const Vec3>(pairs.d.data() + begin, size),
                             disc.self_d()[static_cast<std::size_t>(i)], x, out);
}

}  // namespace vascsim::constraints
