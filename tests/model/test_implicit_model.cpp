// The real-time equilibrium model `implicit` (docs/model/24-implicit.md): its steady state is the static
// equilibrium of quasi_static, its tool force balances the supports (T14), and the tool stiffness it hands to
// the haptic thread is the derivative of the equilibrium force.

#include <gtest/gtest.h>

#include "support/scenes.hpp"

#include <omp.h>
#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

#include "support/run_helpers.hpp"
#include "vascsim/core/blas_control.hpp"
#include "vascsim/experiments/cantilever.hpp"
#include "vascsim/model/implicit_model.hpp"
#include "vascsim/run/simulation.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim {
namespace {

using nlohmann::json;

// The cantilever of the T9 check (2 cells across: 3 x 3 x 23 nodes), loaded in 0.2 s and held to 1.5 s.
// Unlike a vessel wall this beam is not quasi-static: its first bending mode is about 5 Hz, so frames of h =
// 0.1 s (omega h ~ 3) are used, and backward Euler shrinks what is left of the oscillation by 1/(1 + (omega
// h)^2) ~ 0.1 per frame: 13 held frames leave ~1e-13. Frames stop at a residual of 1e-9 of the reactions (or
// at the position-precision floor near 1e-8, which Newton's stall test detects). Tolerance 1e-6 relative:
// above all of these, far below any modelling difference.
TEST(ImplicitModel, CantileverSteadyStateIsTheStaticEquilibrium) {
  CantileverCase c;
  c.cells_across = 2;
  json doc = cantilever_scene(c);
  Simulation stat(parse_scene(doc, "cantilever"));
  const double u_static = test::run_to_end(stat).regions.at(1).displacement_m;
  doc["model"] = "implicit";
  doc["implicit"] = {{"duration_s", 1.5},       {"ramp_time_s", 0.2},    {"output_interval_s", 0.5},
                     {"frame_s", 0.1},          {"rel_tolerance", 1e-9}, {"max_newton_iterations", 30},
                     {"max_cg_iterations", 500}};
  Simulation imp(parse_scene(doc, "cantilever"));
  const StepRecord last = test::run_to_end(imp);
  const double u_implicit = last.regions.at(1).displacement_m;
  std::printf("[ implicit ] cantilever tip: implicit %.10g m, quasi_static %.10g m\n", u_implicit, u_static);
  ASSERT_GT(std::abs(u_static), 0.0);
  EXPECT_NEAR(u_implicit / u_static, 1.0, 1e-6);
  EXPECT_LT(last.report.residual, 1e-6);
}

// The shared catheter block (tests/support/scenes.hpp) pressed 1 mm by the tilted 6 Fr catheter.
json implicit_press_scene(const std::string& model) {
  json doc = test::catheter_pressed_block();
  doc["quasi_static"] = {{"load_steps", 5}, {"rel_tolerance", 1e-9}};
  doc["implicit"] = {{"duration_s", 0.15},      {"ramp_time_s", 0.1},    {"output_interval_s", 0.05},
                     {"frame_s", 0.01},         {"rel_tolerance", 1e-9}, {"max_newton_iterations", 30},
                     {"max_cg_iterations", 300}};
  doc["model"] = model;
  return doc;
}

// T14 for the implicit model: at the held press the tool's force on the tissue balances the support
// reactions (1 %, T14's bound; the residual of 1e-9 of the reactions puts the balance far below it) and
// equals quasi_static's equilibrium force (1e-4 relative: the held frames converge to round-off, see the
// cantilever).
TEST(ImplicitModel, CatheterPressBalancesAndMatchesQuasiStatic) {
  Simulation stat(parse_scene(implicit_press_scene("quasi_static"), "catheter-block"));
  const Vec3 f_static = test::run_to_end(stat).obstacles.at(0).force_vector_n;
  Simulation imp(parse_scene(implicit_press_scene("implicit"), "catheter-block"));
  const StepRecord last = test::run_to_end(imp);
  const Vec3 tool = last.obstacles.at(0).force_vector_n;
  const Vec3 support = last.regions.at(0).force_vector_n;  // the force the base exerts on the tissue
  std::printf(
      "[ implicit ] press: tool (%.6g, %.6g, %.6g) N, support (%.6g, %.6g, %.6g) N, quasi_static z %.6g N\n",
      tool.x(), tool.y(), tool.z(), support.x(), support.y(), support.z(), f_static.z());
  EXPECT_GT(last.obstacles.at(0).contacts, 3);
  EXPECT_LT((tool + support).norm(), 1e-2 * tool.norm());
  EXPECT_LT((tool - f_static).norm(), 1e-4 * f_static.norm());
}

// An offline run refactors in line, on the caller's thread: that must leave the caller's OpenMP thread count
// as it was (a background refactorisation sets its own thread to one; done in line, that once made the whole
// run single-threaded after its first refactorisation). Exact: a thread count.
TEST(ImplicitModel, AnOfflineRefactorisationKeepsTheCallersThreadCount) {
  const int before = omp_get_max_threads();
  omp_set_num_threads(2);
  Simulation imp(parse_scene(implicit_press_scene("implicit"), "catheter-block"));
  test::run_to_end(imp);
  const int after = omp_get_max_threads();
  omp_set_num_threads(before);
  ASSERT_GT(imp.model().info()["factorisations"].get<int>(), 1) << "the press must trigger a refactorisation";
  EXPECT_EQ(after, 2);
}

// The stiffness handed to the haptic thread is the derivative of the equilibrium force: posed at 0.5 mm and
// at 0.5 mm + 1 um (few enough to keep the contact set), each to equilibrium, the force changes by K dp
// within 2 % (the bound; K is exact for the linearised contact problem with the factor refreshed at
// the state, so what is left is the change of the active set and of the contact normals over the step).
TEST(ImplicitModel, ToolStiffnessMatchesAFiniteDifference) {
  json doc = implicit_press_scene("implicit");
  doc["obstacles"][0]["motion_m"] = {0.0, 0.0, 0.0};
  Simulation sim(parse_scene(doc, "catheter-block"));
  auto& model = dynamic_cast<ImplicitModel&>(sim.model());
  const Vec3 tip0(0.0075, 0.0032, 0.00398);
  const Eigen::Quaterniond q = orientation_pointing(Vec3(1, 0, -0.08));
  auto settle = [&](double depth) {
    for (int k = 0; k < 8; ++k) {
      model.set_tool_pose(0, tip0 - Vec3(0, 0, depth), q);
      model.step();
    }
    return model.tool_loads().at(0).force_vector_n;
  };
  // Reach 0.5 mm gradually (the active set follows), then settle there.
  for (int k = 1; k <= 10; ++k) settle(0.05e-3 * k);
  const Vec3 f0 = settle(0.5e-3);
  model.relinearize_now();
  const std::optional<ToolLinearization> lin = model.tool_linearization(0);
  ASSERT_TRUE(lin.has_value());
  const double dp = 1e-6;
  const Vec3 f1 = settle(0.5e-3 + dp);
  // The tool moves by -dp along z; K is d(force on the tissue)/dp.
  const Vec3 predicted = lin->stiffness_n_per_m * Vec3(0, 0, -dp);
  const Vec3 measured = f1 - f0;
  std::printf(
      "[ implicit ] tool stiffness: predicted dF (%.4g, %.4g, %.4g) N, finite difference (%.4g, %.4g, %.4g) "
      "N\n",
      predicted.x(), predicted.y(), predicted.z(), measured.x(), measured.y(), measured.z());
  ASSERT_GT(measured.norm(), 0.0);
  EXPECT_LT((predicted - measured).norm(), 0.02 * measured.norm());
  EXPECT_GT(lin->normal.z(), 0.9);  // the tissue pushes the tool up
}

// A device that jumps 1 mm into the block between two frames (a fast hand, or a frame the machine delayed):
// the model follows in steps of max_tool_step node spacings (0.25 x 0.5 mm here), so no frame starts from a
// tool deep inside the wall. Every frame converges (the default tolerance, 1e-3, within the default 8 Newton
// steps), the force it reports belongs to the position the model used (tool_position_used), the force never
// pulls, and once the tool has arrived the frames settle on quasi_static's equilibrium at the device's pose:
// 1 % relative, for a frame tolerance of 1e-3 (measured: force within about 2.5x the tolerance) and
// quasi_static's 1e-6. With max_tool_step = 0 (the default) the tool is where the device is from the first
// frame.
TEST(ImplicitModel, ADeviceJumpIsFollowedInBoundedSteps) {
  json doc = implicit_press_scene("implicit");
  doc["obstacles"][0]["motion_m"] = {0.0, 0.0, 0.0};
  doc["implicit"].erase("rel_tolerance");
  doc["implicit"].erase("max_newton_iterations");
  doc["implicit"].erase("max_cg_iterations");
  doc["implicit"]["max_tool_step"] = 0.25;
  Simulation sim(parse_scene(doc, "catheter-block"));
  auto& model = dynamic_cast<ImplicitModel&>(sim.model());
  const Vec3 tip0(0.0075, 0.0032, 0.00398);
  const Eigen::Quaterniond q = orientation_pointing(Vec3(1, 0, -0.08));
  const Vec3 target = tip0 - Vec3(0, 0, 1e-3);
  const double step = 0.25 * sim.discretization().mean_spacing();
  model.set_tool_pose(0, tip0, q);
  model.step();
  Vec3 previous = *model.tool_position_used(0);
  int frames = 0;
  for (; frames < 30 && (previous - target).norm() > 1e-12; ++frames) {
    model.set_tool_pose(0, target, q);
    const StepReport r = model.step();
    const Vec3 used = *model.tool_position_used(0);
    EXPECT_LE((used - previous).norm(), step * (1 + 1e-12)) << "frame " << frames;
    EXPECT_TRUE(r.converged) << "frame " << frames << ": residual " << r.residual;
    EXPECT_GE(model.tool_loads().at(0).force_vector_n.dot(Vec3(0, 0, -1)), 0.0)
        << "a pulling tool at frame " << frames;
    previous = used;
  }
  EXPECT_GE(frames, 8);  // 1 mm in steps of 0.125 mm
  EXPECT_LT(frames, 30);
  for (int k = 0; k < 5; ++k) {
    model.set_tool_pose(0, target, q);
    model.step();
  }
  const Vec3 f_followed = model.tool_loads().at(0).force_vector_n;

  json stat_doc = implicit_press_scene("quasi_static");  // the same press to 1 mm by load steps
  stat_doc["quasi_static"]["rel_tolerance"] = 1e-6;
  Simulation stat(parse_scene(stat_doc, "catheter-block"));
  const Vec3 f_static = test::run_to_end(stat).obstacles.at(0).force_vector_n;
  std::printf(
      "[ implicit ] device jump of 1 mm: followed in %d frames, force z %.6g N; quasi_static %.6g N\n",
      frames, f_followed.z(), f_static.z());
  EXPECT_LT((f_followed - f_static).norm(), 1e-2 * f_static.norm());

  doc["implicit"]["max_tool_step"] = 0.0;
  Simulation at_once(parse_scene(doc, "catheter-block"));
  auto& m2 = dynamic_cast<ImplicitModel&>(at_once.model());
  m2.set_tool_pose(0, tip0, q);
  m2.step();
  m2.set_tool_pose(0, target, q);
  m2.step();
  EXPECT_LT((*m2.tool_position_solved(0) - target).norm(), 1e-15);
}

// A tool out of contact goes at once as far as its way touches no node (a catheter moving through the lumen
// at hand speed must not trail the hand by 0.25 node spacings per frame), and only from there in bounded
// steps: a device 5 mm above the block that jumps to 1 mm above it is followed in one frame; one that jumps
// from 3 mm above to 1 mm deep is followed in one frame to within one path sample (half a tool radius, 0.5
// mm) then at most one bounded step past the first touch.
TEST(ImplicitModel, AToolInFreeSpaceGoesAtOnceUpToTheTissue) {
  json doc = implicit_press_scene("implicit");
  doc["obstacles"][0]["motion_m"] = {0.0, 0.0, 0.0};
  doc["implicit"]["max_tool_step"] = 0.25;
  Simulation sim(parse_scene(doc, "catheter-block"));
  auto& model = dynamic_cast<ImplicitModel&>(sim.model());
  // At tip0 the tilted catheter's tip lies beyond the block's edge (x = 6 mm) and its shaft over the edge is
  // 0.12 mm above the top face (z = 3 mm): it first touches between tip0 and 0.15 mm below it.
  const Vec3 tip0(0.0075, 0.0032, 0.00398);
  const Eigen::Quaterniond q = orientation_pointing(Vec3(1, 0, -0.08));
  const double bounded = 0.25 * sim.discretization().mean_spacing();
  model.set_tool_pose(0, tip0 + Vec3(0, 0, 5e-3), q);
  model.step();
  model.set_tool_pose(0, tip0 + Vec3(0, 0, 1e-3), q);
  model.step();
  EXPECT_LT((*model.tool_position_used(0) - (tip0 + Vec3(0, 0, 1e-3))).norm(), 1e-15);
  EXPECT_EQ(model.tool_loads().at(0).contacts, 0);

  model.set_tool_pose(0, tip0 + Vec3(0, 0, 3e-3), q);
  model.step();
  model.set_tool_pose(0, tip0 - Vec3(0, 0, 1e-3), q);
  model.step();
  const double z = model.tool_position_used(0)->z();
  std::printf("[ implicit ] free-space jump: the tool went from %.4g mm to %.4g mm above the touching pose\n",
              3.0, 1e3 * (z - tip0.z()));
  EXPECT_LT(z - tip0.z(), 0.5e-3 + 1e-9);       // at most one path sample short of the tissue
  EXPECT_GT(z - tip0.z(), -0.15e-3 - bounded);  // and not deeper than one bounded step past first touch
}

// In a realtime session a tool in contact waits for a wall that has not caught up
// (implicit.realtime_tool_step): it moves towards the device's pose by at most realtime_tool_step node
// spacings per frame, and only after a frame that handed its force on. A frame budget of 1 ns stops every
// frame before its first Newton step, so the frames are deterministic: with the default hand-off bound none
// hands on, and the tool stays exactly where the first touching frame left it; with a bound the frames meet
// (handoff_max_residual 1e6) it moves by the bounded step per frame; with realtime_tool_step 0 it is at the
// device's pose at once (and the nodes it entered are projected through the wall).
TEST(ImplicitModel, ARealtimeToolWaitsForAWallThatHasNotCaughtUp) {
  const Vec3 tip0(0.0075, 0.0032, 0.00398);  // just above the block (AToolInFreeSpaceGoesAtOnceUpToTheTissue)
  const Eigen::Quaterniond q = orientation_pointing(Vec3(1, 0, -0.08));
  const Vec3 target = tip0 - Vec3(0, 0, 1e-3);
  const int blas = blas_threads();  // set_realtime gives the BLAS one thread
  const auto session = [&](double handoff_max_residual, double realtime_tool_step) {
    json doc = implicit_press_scene("implicit");
    doc["obstacles"][0]["motion_m"] = {0.0, 0.0, 0.0};
    doc["implicit"]["time_budget_s"] = 1e-9;
    doc["implicit"]["handoff_max_residual"] = handoff_max_residual;
    doc["implicit"]["realtime_tool_step"] = realtime_tool_step;
    auto sim = std::make_unique<Simulation>(parse_scene(doc, "catheter-block"));
    auto& model = dynamic_cast<ImplicitModel&>(sim->model());
    model.set_realtime(true);
    model.set_tool_pose(0, tip0, q);
    model.step();
    std::vector<Vec3> solved;  // the model's tool after each frame with the device 1 mm deep
    for (int k = 0; k < 6; ++k) {
      model.set_tool_pose(0, target, q);
      model.step();
      solved.push_back(*model.tool_position_solved(0));
    }
    return std::make_pair(std::move(sim), solved);
  };
  const auto [held_sim, held] = session(1e-2, 0.5);
  const double step = 0.5 * held_sim->discretization().mean_spacing();
  EXPECT_LT(held[0].z(), tip0.z());  // the first frame went down to the tissue and touched it
  for (std::size_t k = 1; k < held.size(); ++k)
    EXPECT_EQ(held[k], held[0]) << "frame " << k << ": the tool moved on from an unconverged wall";
  const auto& held_model = dynamic_cast<ImplicitModel&>(held_sim->model());
  EXPECT_NEAR(held_model.info()["max_tool_lag_m"].get<double>(), (held[0] - target).norm(), 1e-12);

  // (Until a contact pulls: such a frame hands nothing on whatever the bound, and the tool waits again.)
  const auto [moving_sim, moving] = session(1e6, 0.5);
  for (std::size_t k = 1; k < moving.size(); ++k)
    EXPECT_LE((moving[k] - moving[k - 1]).norm(), step * (1 + 1e-12)) << "frame " << k;
  for (std::size_t k = 1; k < 3; ++k) {
    EXPECT_NEAR((moving[k] - moving[k - 1]).norm(), step, 1e-12 * step) << "frame " << k;
    EXPECT_LT(moving[k].z(), moving[k - 1].z()) << "frame " << k;
  }
  const auto [at_hand_sim, at_hand] = session(1e-2, 0.0);
  for (const Vec3& p : at_hand) EXPECT_EQ(p, target);
  set_blas_threads(blas);
}

}  // namespace
}  // namespace vascsim

// The forcing cap (implicit.max_forcing) trades CG iterations per Newton step against Newton steps: it must
// change the work a press takes, never the equilibrium it reaches. Both runs hold the press to a relative
// residual of 1e-9, so their forces agree to round-off; 1e-4 is the bound the press test above holds the
// same frames to against quasi_static.
TEST(ImplicitModel, TheForcingCapChangesTheWorkNotTheEquilibrium) {
  auto press = [](double cap) {
    json doc = implicit_press_scene("implicit");
    doc["implicit"]["max_forcing"] = cap;
    Simulation sim(parse_scene(doc, "catheter-block"));
    const StepRecord last = test::run_to_end(sim);
    return std::make_pair(last.obstacles.at(0).force_vector_n, sim.model().info());
  };
  const auto [loose_force, loose] = press(0.1);
  const auto [tight_force, tight] = press(0.01);
  std::printf("[ implicit ] forcing cap 0.1: %d Newton / %d CG, %.6g N; 0.01: %d / %d, %.6g N\n",
              loose["newton_iterations"].get<int>(), loose["cg_iterations"].get<int>(), loose_force.norm(),
              tight["newton_iterations"].get<int>(), tight["cg_iterations"].get<int>(), tight_force.norm());
  EXPECT_NE(loose["cg_iterations"].get<int>(), tight["cg_iterations"].get<int>()) << "the cap must be read";
  EXPECT_LT((tight_force - loose_force).norm(), 1e-4 * loose_force.norm());
}

// The cap that follows the residual far from the equilibrium (implicit.far_forcing) is for frames with a time
// budget only (WallMultigrid.TheFarForcingCapIsForSolvesWithADeadline has the work it changes): the scene's
// value reaches the Newton solver, an offline press does not change a single CG iteration by it, and a
// realtime session whose budget of 10 s no frame of this small press reaches holds the press at the same
// equilibrium, to round-off (1e-4, as above).
TEST(ImplicitModel, TheFarForcingCapIsForBudgetedFramesAndKeepsTheEquilibrium) {
  const int blas = blas_threads();  // set_realtime gives the BLAS one thread
  auto press = [](double far, bool realtime) {
    json doc = implicit_press_scene("implicit");
    doc["implicit"]["far_forcing"] = far;
    doc["implicit"]["time_budget_s"] = 10.0;
    Simulation sim(parse_scene(doc, "catheter-block"));
    dynamic_cast<ImplicitModel&>(sim.model()).set_realtime(realtime);
    const StepRecord last = test::run_to_end(sim);
    return std::make_pair(last.obstacles.at(0).force_vector_n, sim.model().info());
  };
  const auto [offline_far_force, offline_far] = press(0.25, false);
  const auto [offline_near_force, offline_near] = press(0.0, false);
  EXPECT_EQ(offline_far["far_forcing"].get<double>(), 0.25)
      << "the scene's far_forcing must reach the solver";
  EXPECT_EQ(offline_far["cg_iterations"].get<int>(), offline_near["cg_iterations"].get<int>())
      << "an offline frame must not use the far cap";
  EXPECT_EQ(offline_far_force, offline_near_force);
  const auto [far_force, far] = press(0.25, true);
  const auto [near_force, near] = press(0.0, true);
  std::printf("[ implicit ] realtime, far forcing 0.25: %d Newton / %d CG, %.6g N; off: %d / %d, %.6g N\n",
              far["newton_iterations"].get<int>(), far["cg_iterations"].get<int>(), far_force.norm(),
              near["newton_iterations"].get<int>(), near["cg_iterations"].get<int>(), near_force.norm());
  EXPECT_LT((near_force - far_force).norm(), 1e-4 * far_force.norm());
  set_blas_threads(blas);
}
