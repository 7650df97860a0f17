// The catheter tool and frictionless contact (docs/haptics.md): geometry, device posing, and
// docs/validation.md T14 - at equilibrium the force the tool exerts on the tissue balances the support
// reactions, and so does its moment - for the quasi_static active set and for the xpbd contact constraints.

#include <gtest/gtest.h>

#include "support/scene_errors.hpp"
#include "support/scenes.hpp"

#include <cstdio>
#include <nlohmann/json.hpp>

#include "vascsim/core/error.hpp"
#include "vascsim/model/quasi_static_model.hpp"
#include "vascsim/model/xpbd_model.hpp"
#include "vascsim/run/simulation.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim {
namespace {

using json = nlohmann::json;

TEST(Catheter, SixFrenchTipIsTheForemostPoint) {
  const Vec3 tip(0.01, 0.0, 0.0), dir(0.0, 0.0, -2.0);
  const RigidObstacle c = make_catheter("c", tip, dir, 6 * kMetresPerFrench, 0.02);
  EXPECT_NEAR(c.radius_m, 1e-3, 1e-15);  // 6 Fr = 2 mm
  const constraints::Capsule g = obstacle_at(c, 0.0);
  // The tip lies on the surface; just beyond it is outside, just behind it inside (1e-12 m: round-off).
  EXPECT_NEAR(obstacle_contact(g, tip).value, 0.0, 1e-15);
  EXPECT_GT(obstacle_contact(g, tip + 1e-6 * Vec3::UnitZ() * -1.0).value, 0.0);
  EXPECT_LT(obstacle_contact(g, tip + 1e-6 * Vec3::UnitZ()).value, 0.0);
  // The shaft end is length_m behind the tip.
  EXPECT_NEAR(obstacle_contact(g, tip + Vec3(0, 0, 0.02)).value, 0.0, 1e-15);
  EXPECT_THROW(make_catheter("c", tip, Vec3::Zero(), 2e-3, 0.02), InputError);
  EXPECT_THROW(make_catheter("c", tip, dir, 2e-3, 1e-3), InputError);
}

TEST(Catheter, DevicePoseReproducesTheRestPose) {
  const Vec3 tip(0.001, 0.002, 0.003), dir(1.0, 2.0, -0.5);
  const RigidObstacle c = make_catheter("c", tip, dir, 2e-3, 0.015);
  const constraints::Capsule rest = obstacle_at(c, 0.0);
  const constraints::Capsule posed = obstacle_posed(c, tip, orientation_pointing(dir));
  EXPECT_LT((rest.a - posed.a).norm(), 1e-15);
  EXPECT_LT((rest.b - posed.b).norm(), 1e-15);
  // Turned to point along +x and moved: the tip follows the device position.
  const constraints::Capsule turned = obstacle_posed(c, Vec3(0.1, 0, 0), orientation_pointing(Vec3::UnitX()));
  EXPECT_LT((turned.a - Vec3(0.1 - 1e-3, 0, 0)).norm(), 1e-15);
  EXPECT_LT((turned.b - Vec3(0.1 - 0.014, 0, 0)).norm(), 1e-15);
}

TEST(Catheter, SceneTakesFrenchOrMetresAndRejectsBoth) {
  json doc = json::parse(R"({
    "name": "cat", "model": "quasi_static",
    "geometry": { "type": "box", "min_m": [0, 0, 0], "max_m": [0.004, 0.004, 0.002], "node_spacing_m": 0.001 },
    "regions": [ { "name": "base", "select": { "type": "box", "max_m": [1, 1, 0] }, "bc": { "type": "fixed" } } ],
    "obstacles": [ { "name": "catheter", "shape": "catheter", "tip_m": [0.002, 0.002, 0.003], "direction": [0, 0, -1],
                     "push_m": 0.001 } ]
  })");
  const Scene s = parse_scene(doc, "cat");
  ASSERT_EQ(s.obstacles.size(), 1u);
  EXPECT_NEAR(s.obstacles[0].radius_m, 1e-3, 1e-15);  // default 6 Fr
  EXPECT_LT((s.obstacles[0].motion_m - Vec3(0, 0, -0.001)).norm(), 1e-15);
  json bad = doc;
  bad["obstacles"][0]["diameter_m"] = 0.001;
  bad["obstacles"][0]["diameter_fr"] = 3;
  EXPECT_THROW(parse_scene(bad, "cat"), InputError);
  bad = doc;
  bad["obstacles"][0]["direction"] = {0, 0, 0};
  EXPECT_THROW(parse_scene(bad, "cat"), InputError);
  bad = doc;
  bad["obstacles"][0]["length_m"] = 0.001;  // shorter than the 2 mm diameter
  EXPECT_THROW(parse_scene(bad, "cat"), InputError);
  bad = doc;
  bad["model"] = "explicit";
  EXPECT_THROW(Simulation(parse_scene(bad, "cat")), InputError);
}

// The shared catheter block (tests/support/scenes.hpp), pressed 1 mm.
json catheter_press_scene(const std::string& model) {
  json doc = test::catheter_pressed_block();
  doc["quasi_static"] = {{"load_steps", 3}, {"rel_tolerance", 1e-9}};
  doc["xpbd"] = {
      {"duration_s", 0.4}, {"ramp_time_s", 0.05}, {"output_interval_s", 0.05}, {"damping_per_s", 60}};
  doc["model"] = model;
  return doc;
}

struct Balance {
  Vec3 tool_force = Vec3::Zero(), support_force = Vec3::Zero(), tool_moment = Vec3::Zero(),
       support_moment = Vec3::Zero();
  int contacts = 0;
  double deepest_m = 0.0;
};

// Runs the scene to its end; the support's force and moment (about the tool point) from the nodal
// reactions the model reports.
Balance run_to_balance(Simulation& sim) {
  StepRecord rec;
  for (int k = 1; k <= sim.model().num_steps(); ++k) rec = sim.advance(k);
  EXPECT_TRUE(rec.report.converged);
  Balance b;
  b.tool_force = rec.obstacles.at(0).force_vector_n;
  b.tool_moment = rec.obstacles.at(0).torque_vector_n_m;
  b.contacts = rec.obstacles[0].contacts;
  const RigidObstacle& ob = sim.scene().obstacles[0];
  const Vec3 point = tool_point_at(ob, rec.report.load_factor);
  const Vec3Array& x = sim.model().positions();
  Vec3Array f;
  if (const Vec3Array* fc = sim.model().constraint_forces())
    f = *fc;  // xpbd: what the solver applied, sum lambda grad C / h^2
  else
    sim.energy().forces(x, f);  // quasi_static: the support balances the elastic force
  for (Index i = 0; i < static_cast<Index>(x.size()); ++i) {
    if (!sim.problem().constrained()[i]) continue;
    // xpbd's constraint force on a fixed node is what the elastic constraints did to it: the support
    // pushes back with the opposite. quasi_static: the support force is -f_int.
    const Vec3 support = -f[i];
    b.support_force += support;
    b.support_moment += (x[i] - point).cross(support);
  }
  const constraints::Capsule g = obstacle_at(ob, rec.report.load_factor);
  for (const auto& p : x) b.deepest_m = std::max(b.deepest_m, -obstacle_contact(g, p).value);
  std::printf(
      "[ catheter ] %s: tool force on tissue (%.5g, %.5g, %.5g) N, supports (%.5g, %.5g, %.5g) N; moment "
      "(%.4g, %.4g, %.4g) vs (%.4g, %.4g, %.4g) N m; %d contacts\n",
      sim.model().name().c_str(), b.tool_force.x(), b.tool_force.y(), b.tool_force.z(), b.support_force.x(),
      b.support_force.y(), b.support_force.z(), b.tool_moment.x(), b.tool_moment.y(), b.tool_moment.z(),
      b.support_moment.x(), b.support_moment.y(), b.support_moment.z(), b.contacts);
  return b;
}

// T14 with the quasi_static active set. Tolerance 1 % (T14, docs/validation.md); the Newton residual of 1e-9
// of the reactions puts the actual balance far below it. The moment is compared against |F| x the block size,
// the moment a 1 % force error would make.
TEST(Catheter, QuasiStaticPressBalancesForceAndMoment) {
  Simulation sim(parse_scene(catheter_press_scene("quasi_static"), "catheter-block"));
  const Balance b = run_to_balance(sim);
  EXPECT_GT(b.contacts, 3);
  EXPECT_LT(b.tool_force.z(), 0.0);  // pushes down into the block
  EXPECT_LT((b.tool_force + b.support_force).norm(), 1e-2 * b.tool_force.norm());
  EXPECT_LT((b.tool_moment + b.support_moment).norm(), 1e-2 * b.tool_force.norm() * 0.006);
  EXPECT_GT(b.tool_moment.norm(), 1e-2 * b.tool_force.norm() * 0.006);  // the tilt makes a moment
  EXPECT_LT(b.deepest_m, 1e-12);  // frictionless contact holds nodes on the surface
  // Frictionless: every contact force is normal to the tool, so the force is not along x (the axis) much.
  EXPECT_LT(std::abs(b.tool_force.x()), 0.2 * b.tool_force.norm());
}

// T14 with the catheter against the wall's surface (contact.surface "embedded"), pressed 0.5 mm: the samples'
// forces reach the nodes through their shape functions, so the tool's force and moment balance the supports'
// as the active set's do (same tolerances), and no node enters the tool by more than the penalty's
// penetration (bound 2 um, 4e-3 of the 0.5 mm spacing).
TEST(Catheter, EmbeddedPressBalancesForceAndMoment) {
  json doc = catheter_press_scene("quasi_static");
  doc["contact"] = {{"surface", "embedded"}};
  doc["obstacles"][0]["motion_m"] = {0, 0, -0.0005};
  Simulation sim(parse_scene(doc, "catheter-block"));
  ASSERT_NE(sim.problem().contact_surface(), nullptr);
  const Balance b = run_to_balance(sim);
  EXPECT_GT(b.contacts, 3);
  EXPECT_LT(b.tool_force.z(), 0.0);
  EXPECT_LT((b.tool_force + b.support_force).norm(), 1e-2 * b.tool_force.norm());
  EXPECT_LT((b.tool_moment + b.support_moment).norm(), 1e-2 * b.tool_force.norm() * 0.006);
  EXPECT_GT(b.tool_moment.norm(), 1e-2 * b.tool_force.norm() * 0.006);
  EXPECT_LT(b.deepest_m, 2e-6);
  EXPECT_EQ(sim.model().info().at("contact"), "embedded");
}

// Pressed the full 1 mm, the block folds under the capsule's edge (the node contact's run inverts 30 virtual
// tetrahedra there too). The nodes below the surface are samples of their own, so none sits inside the tool
// by more than the penalty's penetration: measured 3.1 um; bound 10 um, 2 % of the spacing (without them the
// folded second layer sat 0.33 mm inside the tool). In 6 load steps: in 3, the folded last step's Newton
// solve converged or stalled at 3e-6 depending on the BLAS's rounding (machines and thread counts differed);
// in 6 it converges in about 40 iterations of the 60 allowed at one and two threads. Release only (5 s).
TEST(Catheter, EmbeddedPressKeepsTheNodesBelowTheSurfaceOutOfTheToolSlow) {
  json doc = catheter_press_scene("quasi_static");
  doc["contact"] = {{"surface", "embedded"}};
  doc["quasi_static"]["load_steps"] = 6;
  Simulation sim(parse_scene(doc, "catheter-block"));
  const Balance b = run_to_balance(sim);
  EXPECT_LT((b.tool_force + b.support_force).norm(), 1e-2 * b.tool_force.norm());
  EXPECT_LT(b.deepest_m, 1e-5);
}

// The contact block is refused where it cannot apply, at the key that asks for it.
TEST(Catheter, EmbeddedContactIsCheckedAtItsKeys) {
  json doc = catheter_press_scene("xpbd");
  doc["contact"] = {{"surface", "embedded"}};
  std::string m = test::scene_error(doc, "e.json");
  EXPECT_NE(m.find("contact.surface"), std::string::npos) << m;
  EXPECT_NE(m.find("quasi_static"), std::string::npos) << m;  // names the models that take it
  doc = catheter_press_scene("quasi_static");
  doc["contact"] = {{"surface", "nodes"}, {"stiffness_pa_per_m", 1e10}};
  m = test::scene_error(doc, "e.json");
  EXPECT_NE(m.find("stiffness_pa_per_m"), std::string::npos) << m;
  doc["contact"] = {{"surface", "embedded"}, {"sample_spacing_m", -1}};
  m = test::scene_error(doc, "e.json");
  EXPECT_NE(m.find("sample_spacing_m"), std::string::npos) << m;
  doc["contact"] = {{"surface", "embedded"}};
  doc["obstacles"][0]["node_radius_m"] = 1e-4;
  m = test::scene_error(doc, "e.json");
  EXPECT_NE(m.find("obstacles.0.node_radius_m"), std::string::npos) << m;
}

// The same press in xpbd, run to its steady state: force balance to 1 % (the remaining velocity is
// ~0.1 % at 0.4 s with c = 60/s), and the moment to the same relative bound.
TEST(Catheter, XpbdPressBalancesForceAndMomentSlow) {
  Simulation sim(parse_scene(catheter_press_scene("xpbd"), "catheter-block"));
  const Balance b = run_to_balance(sim);
  EXPECT_GT(b.contacts, 3);
  EXPECT_LT(b.tool_force.z(), 0.0);
  EXPECT_LT((b.tool_force + b.support_force).norm(), 1e-2 * b.tool_force.norm());
  EXPECT_LT((b.tool_moment + b.support_moment).norm(), 1e-2 * b.tool_force.norm() * 0.006);
  EXPECT_LT(b.deepest_m, 1e-9);
}

// A device-posed catheter (the haptic session's path): set_tool_pose every step moves it down from
// above the block; the tissue sees the posed tool, not the load-factor motion, and the substeps sweep it
// so the force rises without a jump. On a 1 mm lattice (196 nodes): the posing and the sweep do not depend on
// the resolution, and 130 xpbd steps of the 0.5 mm block took 40 s under the sanitizers.
TEST(Catheter, XpbdFollowsTheDevicePose) {
  json doc = catheter_press_scene("xpbd");
  doc["obstacles"][0]["motion_m"] = {0.0, 0.0, 0.0};
  doc["geometry"]["node_spacing_m"] = 1e-3;
  Simulation sim(parse_scene(doc, "catheter-block"));
  auto& model = dynamic_cast<XpbdModel&>(sim.model());
  const Vec3 tip0(0.0075, 0.0032, 0.00398);
  const Eigen::Quaterniond q = orientation_pointing(Vec3(1, 0, -0.08));
  double previous = 0.0, largest_jump = 0.0;
  for (int k = 1; k <= 130; ++k) {
    const double depth = std::min(k, 100) * 1e-5;  // 1 mm over 100 ms, then hold
    model.set_tool_pose(0, tip0 - Vec3(0, 0, depth), q);
    model.step();
    const double fz = -model.obstacle_loads()[0].force_vector_n.z();
    largest_jump = std::max(largest_jump, std::abs(fz - previous));
    previous = fz;
  }
  const constraints::Capsule g = model.obstacle_geometry(0);
  EXPECT_LT((g.a - (tip0 - Vec3(0, 0, 1e-3) - 1e-3 * (q * Vec3(0, 0, -1)))).norm(), 1e-12);
  EXPECT_GT(previous, 0.0);
  std::printf("[ catheter ] posed press: %.4g N at 1 mm, largest change per 1 ms step %.3g N\n", previous,
              largest_jump);
  EXPECT_LT(largest_jump, 0.25 * previous);  // no jump of a quarter of the final force in one step
}

// quasi_static driven by a device (DeviceDrivenModel, as a haptic session drives it): each frame is the
// equilibrium at the posed tool. Posing the catheter to the depths of the load-stepped press gives the same
// equilibrium force; the tolerance 1e-5 relative is far above the Newton residual of 1e-9 of the reactions
// (the two runs take different predictors, so they agree to the solver tolerance, not bit for bit).
TEST(Catheter, QuasiStaticDrivenByTheDevicePoseMatchesTheLoadSteps) {
  Simulation stepped(parse_scene(catheter_press_scene("quasi_static"), "catheter-block"));
  StepRecord last;
  for (int k = 1; k <= stepped.model().num_steps(); ++k) last = stepped.advance(k);
  const Vec3 f_stepped = last.obstacles.at(0).force_vector_n;

  json doc = catheter_press_scene("quasi_static");
  doc["obstacles"][0]["motion_m"] = {0.0, 0.0, 0.0};
  doc["quasi_static"]["frame_s"] = 0.002;
  Simulation posed(parse_scene(doc, "catheter-block"));
  DeviceDrivenModel* model = posed.model().device_driven();
  ASSERT_NE(model, nullptr);
  const Vec3 tip0(0.0075, 0.0032, 0.00398);
  const Eigen::Quaterniond q = orientation_pointing(Vec3(1, 0, -0.08));
  for (int k = 1; k <= 3; ++k) {
    model->set_tool_pose(0, tip0 - Vec3(0, 0, k * 1e-3 / 3.0), q);
    const StepReport r = model->step();
    EXPECT_TRUE(r.converged);
    EXPECT_NEAR(model->time(), 0.002 * k, 1e-15);
  }
  const Vec3 f_posed = model->tool_loads().at(0).force_vector_n;
  std::printf("[ catheter ] quasi_static posed: (%.6g, %.6g, %.6g) N, load-stepped (%.6g, %.6g, %.6g) N\n",
              f_posed.x(), f_posed.y(), f_posed.z(), f_stepped.x(), f_stepped.y(), f_stepped.z());
  EXPECT_LT((f_posed - f_stepped).norm(), 1e-5 * f_stepped.norm());
  // The same pose again is the same equilibrium.
  model->set_tool_pose(0, tip0 - Vec3(0, 0, 1e-3), q);
  model->step();
  EXPECT_LT((model->tool_loads().at(0).force_vector_n - f_posed).norm(), 1e-5 * f_posed.norm());
}

}  // namespace
}  // namespace vascsim
