// Embedded contact (model/embedded_contact.hpp): the penalty's forces are minus the gradient of its energy,
// its Hessian products the derivative of those forces, and the tool's force is what the nodes receive (the
// shape functions are a partition of unity, so the reaction is consistent with the map); the wall's answer
// to the contact is that force less the residual on the contact's nodes.

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "vascsim/model/embedded_contact.hpp"
#include "vascsim/model/rigid_obstacle.hpp"

namespace vascsim {
namespace {

struct Fixture {
  Vec3Array X;  // rest nodes, m
  ContactSurface surface;
};

// 30 nodes in a 1 mm box under a 2 x 2 mm patch of 400 samples at z = 0; each sample takes 4 random nodes
// with random weights that sum to 1. A sphere of 1 mm radius presses 50 um into the patch from above.
Fixture make_fixture(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<Index> pick(0, 29);
  Fixture f;
  for (int i = 0; i < 30; ++i) f.X.push_back(Vec3(1e-3 * u(rng), 1e-3 * u(rng), -0.5e-3 + 0.5e-3 * u(rng)));
  ContactSurface& s = f.surface;
  s.row_start.push_back(0);
  for (int a = 0; a < 20; ++a)
    for (int b = 0; b < 20; ++b) {
      s.rest_points.push_back(Vec3(-1e-3 + 0.1e-3 * (a + 0.5), -1e-3 + 0.1e-3 * (b + 0.5), 0.0));
      s.area_m2.push_back(1e-8);
      double sum = 0.0;
      std::vector<double> w(4);
      for (double& x : w) sum += (x = 0.5 + 0.5 * u(rng));
      for (double x : w) {
        s.col.push_back(pick(rng));
        s.val.push_back(x / sum);
      }
      s.row_start.push_back(static_cast<Index>(s.col.size()));
    }
  s.stiffness_pa_per_m = 1e11;
  s.finish();
  return f;
}

constraints::Capsule pressing_sphere() {
  return {Vec3(0.1e-3, -0.05e-3, 0.95e-3), Vec3(0.1e-3, -0.05e-3, 0.95e-3), 1e-3};
}

// The penalty's energy summed over every sample, as the contact did before it kept a list of the samples near
// the tools (EmbeddedContact::make_candidates).
double energy_over_every_sample(const Fixture& f, const constraints::Capsule& tool, const Vec3Array& x) {
  const ContactSurface& s = f.surface;
  double e = 0.0;
  for (Index v = 0; v < s.num_samples(); ++v) {
    Vec3 xv = s.rest_points[v];
    for (Index k = s.row_start[v]; k < s.row_start[v + 1]; ++k)
      xv += s.val[static_cast<std::size_t>(k)] *
            (x[s.col[static_cast<std::size_t>(k)]] - f.X[s.col[static_cast<std::size_t>(k)]]);
    const double c = obstacle_contact(tool, xv).value;
    if (c < 0.0) e += 0.5 * s.stiffness_pa_per_m * s.area_m2[static_cast<std::size_t>(v)] * c * c;
  }
  return e;
}

// The samples near the tools are listed once and reused while the tools and the nodes move by less than a
// quarter of the tool's radius (75 um for this 0.3 mm sphere): along a press of 10 steps of 10 um and a slide
// of 30 steps of 20 um across the patch, with the nodes moving about 10 um at random at every step, and then
// the tool held while the nodes move under it by 15 um a step for 20 steps, the energy equals that summed
// over every sample, to the last bit (the same penetrating samples in the same order). A list kept after the
// tool moved farther, or the nodes, misses samples the slide brings in.
TEST(EmbeddedContact, TheSamplesNearTheToolsAreAllThatCanTouchThem) {
  std::mt19937 rng(11);
  Fixture f = make_fixture(rng);
  EmbeddedContact contact(f.surface, f.X, 1);
  std::normal_distribution<double> n(0.0, 6e-6);
  constraints::Capsule tool{Vec3(-0.3e-3, 0.0, 0.3e-3), Vec3(-0.3e-3, 0.0, 0.3e-3), 0.3e-3};  // touching
  Vec3Array x = f.X;
  int touching = 0;
  for (int k = 0; k < 60; ++k) {
    const Vec3 step = k < 10 ? Vec3(0, 0, -10e-6) : k < 40 ? Vec3(20e-6, 0, 0) : Vec3::Zero();
    tool.a += step;
    tool.b += step;
    contact.place(0, tool);
    for (Vec3& p : x) p += k < 40 ? Vec3(n(rng), n(rng), n(rng)) : Vec3(15e-6, 0, 0);
    const double e = contact.energy(x);
    EXPECT_EQ(e, energy_over_every_sample(f, tool, x)) << "step " << k;
    touching += e > 0.0;
  }
  EXPECT_GT(touching, 50);  // the tool was in the patch
}

// Central differences of the energy with a step of 1 nm (1e-6 of the box; the energy is piecewise quadratic,
// so the truncation error is round-off, about 1e-7 of the largest force): within 1e-5 of the largest force.
TEST(EmbeddedContact, ForcesAreMinusTheEnergyGradient) {
  std::mt19937 rng(7);
  Fixture f = make_fixture(rng);
  EmbeddedContact contact(f.surface, f.X, 1);
  contact.place(0, pressing_sphere());
  Vec3Array x = f.X;
  std::normal_distribution<double> n(0.0, 2e-6);
  for (Vec3& p : x) p += Vec3(n(rng), n(rng), n(rng));
  contact.linearize(x);
  ASSERT_GT(contact.active(), 20);
  Vec3Array force(x.size(), Vec3::Zero());
  contact.add_forces(force);
  double largest = 0.0;
  for (const Vec3& g : force) largest = std::max(largest, g.cwiseAbs().maxCoeff());
  ASSERT_GT(largest, 0.0);
  const double h = 1e-9;
  for (std::size_t i = 0; i < x.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      Vec3Array xp = x, xm = x;
      xp[i][k] += h;
      xm[i][k] -= h;
      const double fd = -(contact.energy(xp) - contact.energy(xm)) / (2 * h);
      EXPECT_NEAR(force[i][k], fd, 1e-5 * largest) << "node " << i << " component " << k;
    }
}

// (d^2 U / dx^2) p against the central difference of the forces along p (step 1 nm): within 1e-5 of the
// largest entry (the active set does not change within the step).
TEST(EmbeddedContact, HessianProductIsTheForcesDerivative) {
  std::mt19937 rng(11);
  Fixture f = make_fixture(rng);
  EmbeddedContact contact(f.surface, f.X, 1);
  contact.place(0, pressing_sphere());
  Vec3Array x = f.X, p(f.X.size());
  std::normal_distribution<double> n(0.0, 1.0);
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] += 2e-6 * Vec3(n(rng), n(rng), n(rng));
    p[i] = Vec3(n(rng), n(rng), n(rng));
  }
  const auto forces_at = [&](const Vec3Array& y) {
    Vec3Array g(y.size(), Vec3::Zero());
    contact.linearize(y);
    contact.add_forces(g);
    return g;
  };
  const double h = 1e-9;
  Vec3Array xp = x, xm = x;
  for (std::size_t i = 0; i < x.size(); ++i) xp[i] += h * p[i], xm[i] -= h * p[i];
  const Vec3Array fp = forces_at(xp), fm = forces_at(xm);
  contact.linearize(x);
  Vec3Array Hp(x.size(), Vec3::Zero());
  contact.add_hessian_product(p, Hp);
  double largest = 0.0;
  for (const Vec3& g : Hp) largest = std::max(largest, g.cwiseAbs().maxCoeff());
  ASSERT_GT(largest, 0.0);
  for (std::size_t i = 0; i < x.size(); ++i)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(Hp[i][k], -(fp[i][k] - fm[i][k]) / (2 * h), 1e-5 * largest)
          << "node " << i << " component " << k;
}

// The tool's force is the sum of what the nodes receive (to round-off: the weights sum to 1), points away
// from the tool (the sphere presses down), and its moment about the sphere's centre vanishes (every sample's
// force is along the normal through the centre).
TEST(EmbeddedContact, TheToolFeelsWhatTheNodesReceive) {
  std::mt19937 rng(3);
  Fixture f = make_fixture(rng);
  EmbeddedContact contact(f.surface, f.X, 1);
  const constraints::Capsule sphere = pressing_sphere();
  contact.place(0, sphere);
  contact.linearize(f.X);
  Vec3Array force(f.X.size(), Vec3::Zero());
  contact.add_forces(force);
  Vec3 total = Vec3::Zero();
  for (const Vec3& g : force) total += g;
  const ObstacleLoad load = contact.loads({sphere.a}).at(0);
  EXPECT_EQ(load.contacts, contact.active());
  EXPECT_LT(load.force_vector_n.z(), 0.0);
  EXPECT_NEAR((load.force_vector_n - total).norm(), 0.0, 1e-12 * load.force_vector_n.norm());
  EXPECT_NEAR(load.torque_vector_n_m.norm(), 0.0, 1e-12 * load.force_vector_n.norm() * sphere.radius_m);
  EXPECT_NEAR(contact.squared_force(), load.force_vector_n.squaredNorm(),
              1e-12 * load.force_vector_n.squaredNorm());
  // Nothing penetrates once the sphere is lifted clear.
  contact.place(0, {sphere.a + Vec3(0, 0, 0.1e-3), sphere.a + Vec3(0, 0, 0.1e-3), sphere.radius_m});
  contact.linearize(f.X);
  EXPECT_EQ(contact.active(), 0);
  EXPECT_EQ(contact.energy(f.X), 0.0);
}

// A frame whose tool moved keeps the samples that were in contact (relinearize_carried): the same samples, at
// the moved tool's depths, and none of the samples the move swept into the tool; a sample the tool left drops
// out. Checked against linearize at the same tool pose: the carried set's every force equals the full set's
// at the same sample (to round-off), and the full set is larger.
TEST(EmbeddedContact, ACarriedSetKeepsOnlyTheSamplesThatWereInContact) {
  std::mt19937 rng(11);
  Fixture f = make_fixture(rng);
  EmbeddedContact carried(f.surface, f.X, 1), full(f.surface, f.X, 1);
  const constraints::Capsule sphere = pressing_sphere();
  carried.place(0, sphere);
  carried.linearize(f.X);
  const int before = carried.active();
  ASSERT_GT(before, 5);
  // 30 um deeper and 0.2 mm along x: the contact patch grows and moves.
  const Vec3 move(0.2e-3, 0.0, -30e-6);
  const constraints::Capsule moved{sphere.a + move, sphere.b + move, sphere.radius_m};
  carried.place(0, moved);
  carried.relinearize_carried(f.X);
  full.place(0, moved);
  full.linearize(f.X);
  EXPECT_GT(carried.active(), 0);
  EXPECT_LE(carried.active(), before);
  EXPECT_GT(full.active(), carried.active());
  std::vector<std::pair<Index, double>> in_full;
  full.for_each_contact([&](Index v, double k, const Vec3&) { in_full.push_back({v, k}); });
  int checked = 0;
  carried.for_each_contact([&](Index v, double k, const Vec3& n) {
    const auto it = std::find_if(in_full.begin(), in_full.end(), [&](const auto& p) { return p.first == v; });
    ASSERT_NE(it, in_full.end()) << "sample " << v << " carried but not in contact at the moved pose";
    EXPECT_NEAR(k, it->second, 1e-12 * k);
    EXPECT_NEAR(n.norm(), 1.0, 1e-12);
    ++checked;
  });
  EXPECT_EQ(checked, carried.active());
  // Lifted clear: every carried sample drops out.
  const Vec3 up(0.0, 0.0, 0.2e-3);
  carried.place(0, {sphere.a + up, sphere.b + up, sphere.radius_m});
  carried.relinearize_carried(f.X);
  EXPECT_EQ(carried.active(), 0);
}

// A carried sample the tool left by at most set_carried_gap's gap stays in the carried set, its penalty
// pulling it back; farther ones drop out. A tool translating by d changes each sample's signed distance by at
// most |d| (the distance is 1-Lipschitz), so with a gap of |d| the carried set is the whole previous one.
TEST(EmbeddedContact, ACarriedSetHoldsTheSamplesTheToolLeftWithinTheGap) {
  std::mt19937 rng(13);
  Fixture f = make_fixture(rng);
  EmbeddedContact contact(f.surface, f.X, 1);
  const constraints::Capsule sphere = pressing_sphere();  // 50 um into the surface
  contact.place(0, sphere);
  contact.linearize(f.X);
  const int before = contact.active();
  ASSERT_GT(before, 5);
  ASSERT_LT(contact.loads({sphere.a}).at(0).force_vector_n.z(), 0.0);  // pushes the tissue down
  // Slid 0.2 mm and lifted 20 um: the samples behind it leave, and with the move as the gap all are held.
  const Vec3 slide(0.2e-3, 0.0, 20e-6);
  contact.set_carried_gap(slide.norm());
  contact.place(0, {sphere.a + slide, sphere.b + slide, sphere.radius_m});
  contact.relinearize_carried(f.X);
  EXPECT_EQ(contact.active(), before);
  // Lifted 0.1 mm (every sample 50-100 um clear): held within a gap of 0.1 mm, the samples pull the tissue
  // up towards the tool; with a gap of 40 um all drop out.
  for (const double gap : {0.1e-3, 40e-6}) {
    contact.place(0, sphere);
    contact.linearize(f.X);
    const Vec3 up(0.0, 0.0, 0.1e-3);
    contact.set_carried_gap(gap);
    contact.place(0, {sphere.a + up, sphere.b + up, sphere.radius_m});
    contact.relinearize_carried(f.X);
    if (gap > 50e-6) {
      EXPECT_EQ(contact.active(), before);
      EXPECT_GT(contact.loads({sphere.a + up}).at(0).force_vector_n.z(), 0.0);
    } else {
      EXPECT_EQ(contact.active(), 0);
    }
  }
}

// The wall's answer to the contact (reaction_loads) is the penalty's force minus the residual on the free
// nodes the contact's samples move: with the residual the penalty's own nodal forces, it is zero (those
// nodes then hold the contact alone); a residual on a node no sample moves, or on a prescribed node, changes
// nothing; and the residual's moment comes off the tool's moment. Exact sums: 1e-12 of the force.
TEST(EmbeddedContact, TheWallsAnswerIsThePenaltyLessTheResidualOnTheContactsNodes) {
  std::mt19937 rng(3);
  Fixture f = make_fixture(rng);
  EmbeddedContact contact(f.surface, f.X, 1);
  const constraints::Capsule sphere = pressing_sphere();
  contact.place(0, sphere);
  contact.linearize(f.X);
  ASSERT_GT(contact.active(), 0);
  const std::vector<Vec3> at = {sphere.a};
  const ObstacleLoad penalty = contact.loads(at).at(0);
  const double tol = 1e-12 * penalty.force_vector_n.norm();
  std::vector<char> constrained(f.X.size(), 0);
  Vec3Array residual(f.X.size(), Vec3::Zero());
  contact.add_forces(residual);
  EXPECT_NEAR(contact.reaction_loads(at, f.X, residual, constrained).at(0).force_vector_n.norm(), 0.0, tol);
  // A residual only on nodes no penetrating sample moves.
  std::vector<char> touched(f.X.size(), 0);
  contact.for_each_contact([&](Index v, double, const Vec3&) {
    for (Index k = f.surface.row_start[v]; k < f.surface.row_start[v + 1]; ++k) touched[f.surface.col[k]] = 1;
  });
  residual.assign(f.X.size(), Vec3::Zero());
  Index lone = -1;
  for (std::size_t i = 0; i < f.X.size(); ++i) {
    if (!touched[i]) residual[i] = Vec3(1.0, 2.0, 3.0), lone = static_cast<Index>(i);
  }
  ASSERT_GE(lone, 0);
  ObstacleLoad r = contact.reaction_loads(at, f.X, residual, constrained).at(0);
  EXPECT_NEAR((r.force_vector_n - penalty.force_vector_n).norm(), 0.0, tol);
  // One touched node: its residual comes off the force, its moment off the moment; prescribed, nothing.
  const auto it = std::find(touched.begin(), touched.end(), 1);
  const std::size_t node = static_cast<std::size_t>(it - touched.begin());
  residual.assign(f.X.size(), Vec3::Zero());
  residual[node] = 1e-3 * penalty.force_vector_n.norm() * Vec3(0.3, -0.5, 0.8);
  r = contact.reaction_loads(at, f.X, residual, constrained).at(0);
  EXPECT_NEAR((r.force_vector_n - (penalty.force_vector_n - residual[node])).norm(), 0.0, tol);
  const Vec3 moment = penalty.torque_vector_n_m - (f.X[node] - sphere.a).cross(residual[node]);
  EXPECT_NEAR((r.torque_vector_n_m - moment).norm(), 0.0, tol * sphere.radius_m);
  constrained[node] = 1;
  r = contact.reaction_loads(at, f.X, residual, constrained).at(0);
  EXPECT_NEAR((r.force_vector_n - penalty.force_vector_n).norm(), 0.0, tol);
}

}  // namespace
}  // namespace vascsim
