#pragma once
// `implicit`: the real-time equilibrium model (docs/model/24-implicit.md). Every frame of length h it
// minimises the backward-Euler energy of the point-primitive model,
//     x_{n+1} = argmin  1/(2 h^2) |x - a|^2_M + U(x) - f_ext . x,      a = x_n + h v_n,
// with the prescribed boundary conditions and the tools' frictionless contact, by Newton-PCG
// (newton_equilibrium.hpp) warm-started at a. At haptic time scales the vessel wall is quasi-static (its
// stiffness per node exceeds its inertia m/h^2 by 10^3-10^4), so the answer is the equilibrium, and the cost
// is linear algebra: CG is preconditioned by a sparse Cholesky factor of the assembled meshless Hessian plus
// M/h^2 (meshless_factor.hpp), refactored when the CG counts say the tangent has drifted or the tool has
// travelled far since the factor was built - in the background during a realtime session (the previous factor
// serves until the new one is ready), synchronously otherwise (deterministic runs replay bit for bit).
//
// Between frames the haptic thread extrapolates the force with the wall's linearised response at the tool
// (tool_linearization): from the contact-space compliance W = N P^{-1} N^T of the contacts (N: one row per
// contact, its normal at its node; P the current factor; contact_correction.hpp builds W for the solver
// anyway), the tool stiffness K_t = N_t^T W^{-1} N_t (N_t: the tool's contact normals, zero for the others).
//
// In a realtime session (set_realtime) a frame may stop at its time budget; the residual reached is reported
// in every StepReport.

#include <future>
#include <memory>
#include <optional>

#include "vascsim/model/contact_active_set.hpp"
#include "vascsim/model/device_driven_model.hpp"
#include "vascsim/model/haptic_candidates.hpp"
#include "vascsim/model/meshless_factor.hpp"
#include "vascsim/model/newton_equilibrium.hpp"
#include "vascsim/model/registry.hpp"
#include "vascsim/model/tool_placement.hpp"
#include "vascsim/model/wall_multigrid.hpp"

namespace vascsim {

struct ImplicitSettings {
  double duration_s = 0.02;         ///< simulated time, s
  double ramp_time_s = 0.01;        ///< loads ramp linearly to full over this time, then hold (0: at once), s
  double output_interval_s = 0.01;  ///< time between output points, s (rounded to whole frames)
  double frame_s = 0.01;            ///< backward-Euler step h, one frame, s
  /// Relative force residual at which a frame stops. Measured on the real-time vein session: the tool force
  /// is then the equilibrium force to about 2.5x this fraction (1e-3: 0.26 %, far inside the 5 % a real-time
  /// frame must reach, with a third of the Newton steps and a quarter of the CG iterations of 1e-6; 1e-2: 2.7
  /// %).
  double rel_tolerance = 1e-3;
  int max_newton_iterations = 8;  ///< per frame
  int max_cg_iterations = 20;     ///< per Newton iteration (more means a stale factor: see refactor_*)
  /// The largest forcing term: each Newton step's CG reduces its residual at least this much. A frame's
  /// problem is nearly linear (the tool moved a fraction of a node spacing), so 3 % instead of 10 % saves
  /// Newton steps, each a CG restart plus forces, energies and a relinearisation: in lockstep frames of 1/60
  /// s on the benchmark's press and slide (docs/model/24-implicit.md, "The forcing term"), 263 Newton / 889
  /// CG against 406 / 1,161 at 1 mm/s, 148 / 896 against 180 / 823 at 5 mm/s.
  double max_forcing = 0.03;
  /// In realtime frames with a time budget, far from the equilibrium the cap follows the residual: a Newton
  /// step at relative residual r may stop its CG at min(10 r, far_forcing) where that exceeds max_forcing
  /// (NewtonSettings::far_forcing; 0: max_forcing throughout; frames without a budget always use
  /// max_forcing). Under a hand at 5 mm/s on the real-time vein, realtime frames' felt force 2.5-5.1 % off
  /// (median tick) against 1.8-100 % with max_forcing alone (docs/performance.md section 12).
  double far_forcing = 0.3;
  /// With the tools on the wall's surface: the forcing term of a frame's carried first step (and of each
  /// carried step towards a far pose), NewtonSettings::carried_forcing. The carried step's own linearisation
  /// of the contact leaves it 0.05-0.3 from the equilibrium, so a tighter solve is wasted: in lockstep frames
  /// of 1/60 s on the benchmark's press and slide, 0.1 took 1,741 / 797 CG iterations at 1 / 5 mm/s against
  /// 2,391 / 881 with 0.01 (docs/model/24-implicit.md, "The forcing term").
  double carried_forcing = 0.1;
  /// Realtime sessions: a frame stops at this wall time, partially converged, and the next one goes on from
  /// there (0: no budget), s.
  double time_budget_s = 0.03;
  /// A frame that ends above this relative residual, or unconverged with a contact that pulls, does not hand
  /// its force to the haptic thread (its contact reactions are not yet the equilibrium's): the last frame
  /// that did keeps serving, from its own tool pose.
  double handoff_max_residual = 1e-2;
  /// With the tools on the wall's surface (contact.surface "embedded"): a frame whose tools moved farther
  /// than this many mean node spacings since the last one gets there in steps of at most this length, each
  /// one linear response of the wall with the contact set carried from the step before (a few
  /// conjugate-gradient iterations round the tool), before its Newton iterations (0: in one step). The tools
  /// still end every frame at the device's pose. A whole spacing: with half of one, frames at 2 mm/s that
  /// came late took a carried step more, came later still, and settled at half the rate (docs/performance.md
  /// section 12).
  double contact_substep = 1.0;
  /// With the tools on the wall's surface (contact.surface "embedded") a frame hands its force on below this
  /// relative residual instead of handoff_max_residual. The force handed on is the wall's answer to the
  /// contact (EmbeddedContact::reaction_loads), which stays near the equilibrium's where the penalty's own
  /// force is far off (a sample a micrometre off carries milli-newtons): on the real-time vein under a hand
  /// at 1 mm/s, frames at residuals of 0.1-0.3 handed on forces within 4 % of the continuum. The frame
  /// before must have ended below it too. Higher thresholds let through frames of a wall thrown off by a
  /// hand faster than the frames (at 5 mm/s, 0.44-0.75 with 12 N where the continuum has 10 mN).
  double handoff_surface_residual = 0.3;
  /// With the tools on the wall's surface: a frame whose tools press on along their last frame's move starts
  /// from the wall's motion over that frame, scaled to the new move, instead of the carried step (a frame
  /// that starts there is close to its equilibrium: in lockstep frames of 1/60 s on the benchmark's 1 mm/s
  /// press, one Newton step of 3-4 CG iterations against three of about 20), when both ends of that frame
  /// were within this relative residual of their equilibria (0: never). Above it the motion is mostly the
  /// solver's correction, and a prediction from it runs away. A tool that slides along the wall has its dent
  /// carried along instead.
  double warm_start_residual = 0.1;
  /// Newton steps every frame takes before time_budget_s can end it, with the tools on the wall's surface (0:
  /// the budget alone decides).
  int min_newton_iterations = 0;
  /// "auto": the wall multigrid where the nodes form a wall lattice (wall_multigrid.hpp), else "meshless" (a
  /// factor of the Hessian); "multigrid", "meshless", or "tet" (linear tets, for comparison).
  std::string preconditioner = "auto";
  /// With the multigrid: conjugate gradients and the smoothing on the Hessian product in single precision
  /// (single_precision_hessian.hpp), where the energy allows it.
  bool single_precision = true;
  /// With single_precision and a tolerance of 1e-4 or looser: the residuals' internal forces in float too,
  /// from the linearisation the products use (NewtonSettings::single_precision_forces). Off only to measure
  /// what it saves.
  bool single_precision_forces = true;
  /// With the multigrid, the coarse level is rebuilt every this many frames (in the background in a realtime
  /// session).
  int level_refresh_frames = 6;
  /// With the multigrid and the tools on the wall's surface: a Newton step after a frame's first whose
  /// contact samples differ from the window's forms the window round the tools again at its own state
  /// (NewtonSettings::follow_state, WallMultigrid::follow_state). Off only to measure what it saves.
  bool window_each_newton_step = true;
  bool line_search = true;  ///< Armijo line search in every Newton iteration (off: whole steps)
  /// With line_search and the tools on the wall's surface: each Newton step is taken whole first, and
  /// searched only when the force residual there is no smaller (NewtonSettings::deferred_line_search): the
  /// two energy evaluations of a frame's first step are saved where the step is good.
  bool deferred_line_search = true;
  int haptic_candidates = 24;  ///< contacts and near contacts handed to the haptic thread (0: K only)
  /// Refactor when CG reduced the residual by less than this per iteration (NewtonResult::cg_rate: about 0.1
  /// with a fresh factor, towards 1 as it goes stale),
  double refactor_cg_rate = 0.3;
  int refactor_cg_iterations = 12;  ///< ... or a Newton iteration needed more CG iterations than this,
  double refactor_residual = 0.0;   ///< ... or a frame ended above this relative residual (0: not a trigger),
  double refactor_travel = 0.5;     ///< ... or a tool travelled this many node spacings since the factor
  /// A device-posed tool in contact moves by at most this many node spacings per frame; one out of contact
  /// goes at once as far as its way touches no node, then by at most this much (0: always at once, the
  /// default: every frame solves at the device's pose, and a frame the budget stops is continued by the
  /// next). With a bound, a frame never starts from a tool that jumped deep into the wall, but under a fast
  /// hand or a slow frame the model's tool trails the device.
  double max_tool_step = 0.0;
  /// In a realtime session, with the tools at the nodes (contact.surface "nodes"; the surface's tools reach
  /// the device's pose by contact_substep's steps) and max_tool_step 0: a tool in contact moves towards the
  /// device's pose by at most this many node spacings per frame, and only after a frame that handed its force
  /// on (its wall near its equilibrium); after one that did not, it waits for the wall. A tool placed at the
  /// device's pose every frame (0) runs ahead of a wall whose frames stop at the budget unconverged, and the
  /// nodes it then enters are projected through the wall: in 10 s soaks of the real-time vein (`vascsim
  /// soak`, seed 1) the wall inverted at the first contacts and no frame handed on a force; with 0.5 none
  /// inverted and the tissue's force reached the hand. The price is the tool's lag behind a hand faster than
  /// the frames (reported: max_tool_lag_m, the HUD).
  double realtime_tool_step = 0.5;
};

/// Reads the `implicit` block of a scene (docs/scene-format.md).
ImplicitSettings read_implicit_settings(JsonReader& block);

/// The registry entry (registry.cpp).
ModelEntry implicit_model_entry();

class ImplicitModel final : public Model, public DeviceDrivenModel {
 public:
  ImplicitModel(const Problem& problem, const ImplicitSettings& settings);
  ~ImplicitModel() override;
  std::string name() const override { return "implicit"; }
  int num_steps() const override { return num_steps_; }
  StepReport advance(int k) override;
  const Vec3Array& positions() const override { return x_; }
  double load_factor() const override { return s_; }
  nlohmann::json info() const override;
  std::vector<ObstacleLoad> obstacle_loads() const override { return loads_; }
  DeviceDrivenModel* device_driven() override { return this; }

  void set_tool_pose(std::size_t tool, const Vec3& position_m,
                     const Eigen::Quaterniond& orientation) override;
  StepReport step() override;
  double time() const override { return t_; }
  double frame_length_s() const override { return h_; }
  std::vector<ObstacleLoad> tool_loads() const override { return loads_; }
  std::optional<Vec3> tool_position_used(std::size_t tool) const override { return handoff_points_.at(tool); }
  std::optional<Vec3> tool_position_solved(std::size_t tool) const override {
    return tools_.points(s_).at(tool);
  }
  std::optional<ToolLinearization> tool_linearization(std::size_t tool) const override;
  void set_realtime(bool realtime) override;

  const Vec3Array& velocities() const { return v_; }
  /// Factors built so far (the one at rest included).
  int factorisations() const { return factorisations_; }
  /// Recomputes every tool's linearisation now, with a factor built at the current state (tests,
  /// experiments).
  void relinearize_now();

 private:
  struct Factor;  // a factor and the linearisation computed with it
  void place_tools(double s);
  void advance_tools(double step_spacings);  // towards the device poses, bounded where they meet tissue
  bool tools_bounded() const;                // the tools follow the device in advance_tools' steps
  double free_travel(
      std::size_t tool) const;  // how far a tool can go towards its pose before it touches a node, m
  void prepare_frame(double s, const Vec3Array& f_ext);  // prescribed nodes, warm start, tools, contacts
  void approach_tools(double s,
                      const Vec3Array& f_ext);          // contact_substep's continuation to the device poses
  std::vector<Vec3> frame_goal_points(double s) const;  // where this frame's tools end
  bool warm_start_from_motion(
      const std::vector<Vec3>& targets);  // warm_start_residual's start; false where it does not apply
  std::optional<Vec3> move_along_wall(std::size_t tool, const std::vector<Vec3>& targets)
      const;  // a tool in contact: the part of its move to targets along the wall; else nullopt
  void advect_with_tools(
      const std::vector<Vec3>& targets);  // otherwise, with a tool sliding: its dent moved along with it
  bool thrown_off() const;  // the last solve left the wall far from any equilibrium (or not finite)
  void recover();           // back to safe_
  void maybe_refactor(const NewtonResult& r);  // the drift triggers
  /// A factor at x, refilling `reuse` (a factor no frame uses any more) when given.
  std::unique_ptr<Factor> build_factor(const Vec3Array& x, std::unique_ptr<Factor> reuse = nullptr) const;
  void install(std::unique_ptr<Factor> f);
  void poll_background();
  void linearize();          // every tool's linearisation from the contact compliance
  void refresh_multigrid();  // the multigrid's coarse level, at the refresh rate
  void poll_multigrid();     // install a level built in the background

  const Problem& problem_;
  ImplicitSettings settings_;
  double h_ = 0.0;
  int num_steps_ = 0;
  double t_ = 0.0, s_ = 0.0;
  bool realtime_ = false;
  bool last_handoff_ = true;  // the last frame handed its force on (realtime_tool_step lets the tool move)
  Vec3Array x_, v_, anchor_, x_old_;
  // warm_start_residual: the wall's motion over the last frame and its tools' move, whether both ends of that
  // frame were near their equilibria, the tools' points of the frame being solved and their move from the
  // last one.
  Vec3Array last_motion_;
  std::vector<Vec3> last_tool_move_, frame_tool_points_, frame_tool_move_;
  bool motion_trusted_ = false, start_near_equilibrium_ = true, warm_started_ = false;
  long long warm_started_frames_ = 0, advected_frames_ = 0;
  bool tools_moved_ =
      false;  // a tool moved since the last frame (its first Newton step carries the contacts)
  FreeDofs free_;
  ContactActiveSet contacts_;
  std::optional<EmbeddedContact> embedded_;  // the tools meet the wall's surface (contact.surface "embedded")
  ToolPlacement tools_;
  NewtonEquilibrium newton_;
  std::unique_ptr<EquilibriumPreconditioner> tet_;  // "tet" preconditioner
  std::unique_ptr<WallMultigrid> multigrid_;        // "multigrid"
  std::unique_ptr<WallMultigrid::Level> level_spare_;
  std::future<std::unique_ptr<WallMultigrid::Level>> level_pending_;
  std::unique_ptr<SinglePrecisionHessian> single_;  // single-precision products with the multigrid
  long long frames_since_level_ = 0;
  std::unique_ptr<Factor> factor_;                // "meshless": the factor in use
  std::unique_ptr<Factor> spare_;                 // the one it replaced, refilled by the next refactorisation
  std::future<std::unique_ptr<Factor>> pending_;  // a factor being built in the background
  std::vector<Vec3> factor_tool_points_;          // tool points when the factor in use was built
  std::vector<ObstacleLoad> loads_;   // the handed-on loads (the last frame below handoff_max_residual)
  std::vector<Vec3> handoff_points_;  // the tools' points of that frame
  long long stale_handoffs_ = 0;
  long long substeps_ = 0;  // contact_substep's continuation steps, all frames
  // Tools on the wall's surface: the state of the last frame that handed on, with its tools, which a frame
  // that throws the wall off goes back to (thrown_off, recover).
  struct SafeState {
    Vec3Array x;
    std::vector<ToolPlacement::Pose> tools;
    std::vector<Vec3> frame_tool_points;
    double residual = 0.0;
  };
  std::optional<SafeState> safe_;
  long long recoveries_ = 0;
  long long disagreements_ = 0;  // frames not handed on: the penalty and the wall's answer disagreed
  bool catching_up_ = false;     // the tools follow the device in bounded steps since a frame went back
  static constexpr double kMaxCarriedSteps = 3.0;  // a frame's carried steps to the device's pose, at most
  // The catch-up's step, node spacings: half of one (a whole one, on the vein piece held 2 mm deep with one
  // Newton step a frame, threw the wall off twice more and handed on 19 mN where the equilibrium has 12 mN).
  static constexpr double kCatchUpStep = 0.5;
  // A frame with the tools on the wall's surface hands on only where the penalty's force and the wall's
  // answer are within this factor of each other (penalty_agrees).
  static constexpr double kPenaltyAgreement = 0.25;
  bool penalty_agrees(const std::vector<ObstacleLoad>& penalty, const std::vector<ObstacleLoad>& wall) const;
  double tool_step_spacings() const;  // the bound on a frame's tool travel, node spacings (0: none)
  std::vector<std::optional<ToolLinearization>> linearization_;  // per tool, after the last frame
  std::unique_ptr<HapticCandidates> candidates_;
  double spacing_ = 0.0;
  int factorisations_ = 0;
  long long frames_ = 0, newton_total_ = 0, cg_total_ = 0, out_of_time_ = 0, unconverged_ = 0;
  double last_residual_ = 0.0, worst_residual_ = 0.0;
  double max_tool_lag_ = 0.0;  // the farthest a tool trailed its device pose, m
  struct {
    double frame_s = 0.0, solve_s = 0.0, refactor_s = 0.0, linearize_s = 0.0;
  } split_;  // wall time per phase, summed over the frames
};

}  // namespace vascsim
