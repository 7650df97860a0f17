// The per-node compliance cache of the equilibrium solvers (model/node_compliance.hpp): its 3 x 3 couplings
// are the blocks of P^{-1}, it solves a node once per factor version, and a new version starts afresh.

#include <gtest/gtest.h>

#include <random>

#include "vascsim/model/node_compliance.hpp"
#include "vascsim/run/simulation.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim {
namespace {

// A dense SPD "factor": P^{-1} applied exactly, a version to bump, and a count of the columns it solved.
class DensePreconditioner final : public EquilibriumPreconditioner {
 public:
  explicit DensePreconditioner(Eigen::Index n) {
    std::mt19937_64 rng(3);
    std::normal_distribution<double> g;
    Eigen::MatrixXd B(n, n);
    for (Eigen::Index i = 0; i < n; ++i)
      for (Eigen::Index j = 0; j < n; ++j) B(i, j) = g(rng);
    inverse_ = (B * B.transpose() + static_cast<double>(n) * Eigen::MatrixXd::Identity(n, n)).inverse();
  }
  bool apply(const Vec3Array&, Vec3Array&) const override { return false; }
  nlohmann::json info() const override { return {}; }
  bool solve_columns(const Eigen::MatrixXd& B, Eigen::MatrixXd& X) const override {
    X = inverse_ * B;
    columns += B.cols();
    return true;
  }
  long long version() const override { return version_; }
  const Eigen::MatrixXd& inverse() const { return inverse_; }
  long long version_ = 1;
  mutable long long columns = 0;

 private:
  Eigen::MatrixXd inverse_;
};

TEST(NodeCompliance, CouplingsAreBlocksOfTheInverseAndEachNodeIsSolvedOncePerFactor) {
  const Scene scene = load_scene(std::string(VASCSIM_SOURCE_DIR) + "/tests/data/haptic-block.json",
                                 {"geometry.node_spacing_m=0.001"});
  Simulation sim(scene);
  const FreeDofs free(sim.problem());
  DensePreconditioner P(free.size());
  NodeCompliance cache(free, /*capacity=*/4);
  const std::vector<Index> a = {free.nodes[3], free.nodes[10], free.nodes[20]};
  ASSERT_TRUE(cache.prepare(a, P));
  EXPECT_EQ(P.columns, 9);
  // C_cd is the (c, d) block of P^{-1}, exactly (it is a copy of the solve's columns).
  for (Index c : a)
    for (Index d : a) {
      const Mat3 expected = P.inverse().block<3, 3>(3 * free.slot[static_cast<std::size_t>(c)],
                                                    3 * free.slot[static_cast<std::size_t>(d)]);
      EXPECT_EQ((cache.coupling(c, d) - expected).cwiseAbs().maxCoeff(), 0.0);
    }
  // The same nodes again, and one more: only the new node is solved.
  std::vector<Index> b = a;
  b.push_back(free.nodes[30]);
  ASSERT_TRUE(cache.prepare(b, P));
  EXPECT_EQ(P.columns, 12);
  // Beyond the capacity (4) the least recently used go; the nodes asked for now are all kept.
  ASSERT_TRUE(cache.prepare({free.nodes[40], free.nodes[41]}, P));
  EXPECT_EQ(P.columns, 18);
  EXPECT_NO_THROW(cache.coupling(free.nodes[40], free.nodes[41]));
  // A new factor version: everything is solved again.
  ++P.version_;
  ASSERT_TRUE(cache.prepare(a, P));
  EXPECT_EQ(P.columns, 27);
  EXPECT_EQ(cache.version(), 2);
}

}  // namespace
}  // namespace vascsim
