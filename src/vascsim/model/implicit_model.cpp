#include "vascsim/model/implicit_model.hpp"

#include <omp.h>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <algorithm>
#include <cmath>
#include <limits>

#include "vascsim/core/blas_control.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/core/stopwatch.hpp"

namespace vascsim {

// A factor of the Newton matrix at a state, and the tools' linearisations computed with it.
struct ImplicitModel::Factor {
  std::unique_ptr<MeshlessFactor> factor;
  Vec3Array x;                    // the state it was built at
  std::vector<Vec3> tool_points;  // the tools' points then
};

ImplicitSettings read_implicit_settings(JsonReader& b) {
  const ImplicitSettings d;
  ImplicitSettings s;
  const TimeSchedule schedule = read_time_schedule(b, {d.duration_s, d.ramp_time_s, d.output_interval_s});
  s.duration_s = schedule.duration_s;
  s.ramp_time_s = schedule.ramp_time_s;
  s.output_interval_s = schedule.output_interval_s;
  s.frame_s = b.number("frame_s", d.frame_s, 1e-6, 1.0);
  s.rel_tolerance = b.number("rel_tolerance", d.rel_tolerance, 1e-14, 0.1);
  s.max_newton_iterations = b.integer("max_newton_iterations", d.max_newton_iterations, 1, 1000);
  s.max_cg_iterations = b.integer("max_cg_iterations", d.max_cg_iterations, 1, 100000);
  s.time_budget_s = b.number("time_budget_s", d.time_budget_s, 0.0, 10.0);
  s.handoff_max_residual = b.number("handoff_max_residual", d.handoff_max_residual, 1e-14, 1e6);
  s.preconditioner = b.string("preconditioner", d.preconditioner, {"auto", "multigrid", "meshless", "tet"});
  s.single_precision = b.boolean("single_precision", d.single_precision);
  s.single_precision_forces = b.boolean("single_precision_forces", d.single_precision_forces);
  s.level_refresh_frames = b.integer("level_refresh_frames", d.level_refresh_frames, 1, 1000000);
  s.window_each_newton_step = b.boolean("window_each_newton_step", d.window_each_newton_step);
  s.line_search = b.boolean("line_search", d.line_search);
  s.deferred_line_search = b.boolean("deferred_line_search", d.deferred_line_search);
  s.haptic_candidates = b.integer("haptic_candidates", d.haptic_candidates, 0, 24);
  s.refactor_cg_rate = b.number("refactor_cg_rate", d.refactor_cg_rate, 0.0, 1.0);
  s.refactor_cg_iterations = b.integer("refactor_cg_iterations", d.refactor_cg_iterations, 1, 100000);
  s.refactor_residual = b.number("refactor_residual", d.refactor_residual, 0.0, 1e6);
  s.refactor_travel = b.number("refactor_travel", d.refactor_travel, 0.0, 1e6);
  s.max_tool_step = b.number("max_tool_step", d.max_tool_step, 0.0, 1e6);
  s.realtime_tool_step = b.number("realtime_tool_step", d.realtime_tool_step, 0.0, 1e6);
  s.contact_substep = b.number("contact_substep", d.contact_substep, 0.0, 1e6);
  s.warm_start_residual = b.number("warm_start_residual", d.warm_start_residual, 0.0, 1e6);
  s.handoff_surface_residual = b.number("handoff_surface_residual", d.handoff_surface_residual, 1e-14, 1e6);
  s.min_newton_iterations = b.integer("min_newton_iterations", d.min_newton_iterations, 0, 1000);
  s.max_forcing = b.number("max_forcing", d.max_forcing, 1e-6, 0.5);
  s.far_forcing = b.number("far_forcing", d.far_forcing, 0.0, 0.5);
  s.carried_forcing = b.number("carried_forcing", d.carried_forcing, 1e-6, 0.5);
  b.finish();
  return s;
}

namespace {
NewtonSettings newton_settings(const ImplicitSettings& s, double spacing_m) {
  NewtonSettings n;
  n.rel_tolerance = s.rel_tolerance;
  n.max_newton_iterations = s.max_newton_iterations;
  n.max_cg_iterations = s.max_cg_iterations;
  n.max_contact_passes = 50;
  n.line_search = s.line_search;
  n.deferred_line_search = s.deferred_line_search;
  n.follow_state = s.window_each_newton_step;
  // Contacts at the nodes that pull are let go below a residual of 1e-3 (releasing at any residual was
  // measured no better: docs/performance.md section 12).
  n.release_below_residual = 1e-3;
  // A frame's tool enters the wall by a whole frame's travel before the first Newton step (embedded contact).
  n.contact_normal_stiffness_only = true;
  n.min_newton_iterations = s.min_newton_iterations;
  n.max_forcing = s.max_forcing;
  n.far_forcing = s.far_forcing;
  n.carried_forcing = s.carried_forcing;
  // The residuals' forces in float from the products' linearisation (one linearisation a Newton step instead
  // of two; about 1e-6 of the forces: docs/model/24-implicit.md), where the tolerance leaves that a hundred
  // times over.
  n.single_precision_forces = s.single_precision && s.single_precision_forces && s.rel_tolerance >= 1e-4;
  // A frame's Newton step moves no node farther than a node spacing (a carried step: twice the tools' move).
  n.max_step_m = spacing_m;
  return n;
}
}  // namespace

ModelEntry implicit_model_entry() {
  ModelEntry e;
  e.name = "implicit";
  e.summary =
      "real-time equilibrium: backward Euler solved by Newton-CG with a sparse Cholesky factor of the "
      "meshless Hessian (the real-time default)";
  e.capabilities = {.dynamic = true,
                    .takes_tools = true,
                    .device_driven = true,
                    .releases_regions = false,
                    .quadratic_basis = true,
                    .wall_support_default = true,
                    .quadratic_stabilizer_default = true,
                    .embedded_contact = true};
  e.read_settings = [](JsonReader& block) { return std::any(read_implicit_settings(block)); };
  e.make = [](const Problem& problem, const std::any& settings) -> std::unique_ptr<Model> {
    return std::make_unique<ImplicitModel>(problem, settings_as<ImplicitSettings>(settings));
  };
  e.schedule = [](const std::any& settings) {
    const auto& s = settings_as<ImplicitSettings>(settings);
    return TimeSchedule{s.duration_s, s.ramp_time_s, s.output_interval_s};
  };
  return e;
}

ImplicitModel::ImplicitModel(const Problem& problem, const ImplicitSettings& settings)
    : problem_(problem),
      settings_(settings),
      x_(problem.discretization().rest_positions()),
      free_(problem),
      contacts_(problem, free_, problem.contact_surface() == nullptr),
      tools_(problem.tools()),
      newton_(problem, free_, contacts_, newton_settings(settings, problem.discretization().mean_spacing())) {
  if (!(settings.frame_s > 0.0) || !(settings.output_interval_s > 0.0) || !(settings.duration_s > 0.0))
    throw InputError("implicit: frame_s, output_interval_s and duration_s must be > 0");
  if (problem.num_constrained() == 0)
    throw InputError("key 'regions': the implicit model needs a fixed or displacement region (supports)");
  // Whole frames per output interval, so output times are exact.
  const long long per_output =
      static_cast<long long>(std::ceil(settings.output_interval_s / settings.frame_s - 1e-9));
  h_ = settings.output_interval_s / static_cast<double>(per_output);
  num_steps_ = static_cast<int>(std::ceil(settings.duration_s / settings.output_interval_s - 1e-9));
  v_.assign(x_.size(), Vec3::Zero());
  spacing_ = problem.discretization().mean_spacing();
  if (const ContactSurface* surface = problem.contact_surface()) {
    embedded_.emplace(*surface, problem.discretization().rest_positions(), problem.tools().size());
    newton_.set_embedded_contact(&*embedded_);
  }
  loads_.assign(problem.tools().size(), ObstacleLoad{});
  // The continuation of contact_substep moves the tools itself (ToolPlacement::advance), as bounded steps do.
  tools_.set_bounded(tools_bounded());
  place_tools(0.0);
  handoff_points_ = tools_.points(0.0);
  // Candidates within half a node spacing of a tool: more than a tool moves in a frame at hand speed.
  candidates_ = std::make_unique<HapticCandidates>(free_, settings.haptic_candidates,
                                                   0.5 * problem.discretization().mean_spacing());
  std::string kind = settings.preconditioner;
  if (kind == "auto") kind = WallMultigrid::supports(problem) ? "multigrid" : "meshless";
  if (kind == "multigrid" && !WallMultigrid::supports(problem))
    throw InputError(
        "key 'implicit.preconditioner': \"multigrid\" needs a wall whose nodes form a lattice (geometry "
        "type vessel or tube) with one energy point per node; use \"meshless\"");
  std::string described;
  if (kind == "tet") {
    tet_ = std::make_unique<TetStiffnessPreconditioner>(problem, free_, "cholesky");
    newton_.set_preconditioner(tet_.get());
    described = "tet stiffness";
  } else if (kind == "multigrid") {
    WallMultigridOptions o;
    o.inv_h2 = 1.0 / (h_ * h_);
    multigrid_ = std::make_unique<WallMultigrid>(problem, free_, contacts_, o);
    if (embedded_) multigrid_->set_embedded_contact(&*embedded_);
    multigrid_->install(multigrid_->build_level(x_));
    newton_.set_preconditioner(multigrid_.get());
    if (settings.single_precision && SinglePrecisionHessian::supports(problem.energy())) {
      single_ = std::make_unique<SinglePrecisionHessian>(problem.energy());
      newton_.set_single_precision(single_.get());
    }
    described = fmt::format("wall multigrid, {} coarse nodes, level built in {:.2f} s{}",
                            multigrid_->info()["coarse_nodes"].get<long long>(),
                            multigrid_->last_level_seconds(), single_ ? ", single-precision products" : "");
  } else {
    install(build_factor(x_));
    described = fmt::format("meshless factor, nnz(L) {:.3g}, {:.2f} s", factor_->factor->stats().nnz_l,
                            factor_->factor->build_seconds());
  }
  spdlog::info("implicit: frame {:.4g} s, {} frames per output, {} outputs; preconditioner {}", h_,
               per_output, num_steps_, described);
}

ImplicitModel::~ImplicitModel() {
  if (pending_.valid()) pending_.wait();  // the jobs read this model's problem
  if (level_pending_.valid()) level_pending_.wait();
}

void ImplicitModel::set_realtime(bool realtime) {
  realtime_ = realtime;
  tools_.set_bounded(tools_bounded());
  // One BLAS thread: an OpenBLAS pool spinning on both cores would starve the haptic thread.
  if (realtime) set_blas_threads(1);
}

void ImplicitModel::place_tools(double s) {
  for (std::size_t o = 0; o < tools_.size(); ++o) {
    if (embedded_)
      embedded_->place(o, tools_.geometry(o, s));
    else
      contacts_.place(o, tools_.geometry(o, s));
  }
}

double ImplicitModel::free_travel(std::size_t o) const {
  // The way is sampled at poses half a tool radius apart (so a fast tool cannot pass through a thin wall
  // between two frames), over at most 128 radii per frame (256 samples: the check stays a few milliseconds).
  const double d = tools_.distance_to_target(o);
  if (d <= 0.0) return std::numeric_limits<double>::infinity();
  const double sample = 0.5 * problem_.tools()[o].radius_m;
  const double reach = std::min(d, 256.0 * sample);
  const int samples = std::max(1, static_cast<int>(std::ceil(reach / sample)));
  for (int k = 1; k <= samples; ++k) {
    const double f = (reach / d) * static_cast<double>(k) / samples;
    const constraints::Capsule g = tools_.geometry_towards_target(o, f);
    for (Index i : free_.nodes)
      if (obstacle_contact(g, x_[static_cast<std::size_t>(i)]).value < 0.0) return reach * (k - 1) / samples;
  }
  return reach < d ? reach : std::numeric_limits<double>::infinity();
}

bool ImplicitModel::tools_bounded() const {
  return settings_.max_tool_step > 0.0 || (realtime_ && !embedded_ && settings_.realtime_tool_step > 0.0) ||
         (embedded_ && settings_.contact_substep > 0.0);
}

void ImplicitModel::advance_tools(double step_spacings) {
  // A tool out of contact goes at once as far as its way to the device's pose touches no node (a catheter
  // moving through the lumen at hand speed); from there, or when it is in contact, it moves by at most
  // step_spacings node spacings per frame.
  const double bounded = step_spacings * spacing_;
  for (std::size_t o = 0; o < tools_.size(); ++o) {
    const double step = loads_[o].contacts > 0 ? bounded : free_travel(o) + bounded;
    max_tool_lag_ = std::max(max_tool_lag_, tools_.advance(o, step));
  }
}

void ImplicitModel::set_tool_pose(std::size_t tool, const Vec3& position_m,
                                  const Eigen::Quaterniond& orientation) {
  tools_.pose(tool, position_m, orientation);
}

std::unique_ptr<ImplicitModel::Factor> ImplicitModel::build_factor(const Vec3Array& x,
                                                                   std::unique_ptr<Factor> reuse) const {
  // A factor that served before keeps its Hessian pattern and CHOLMOD's ordering and symbolic analysis (a
  // quarter to a third of building one from nothing): only the numbers are refilled and refactored.
  auto f = reuse ? std::move(reuse) : std::make_unique<Factor>();
  if (!f->factor) {
    MeshlessFactorOptions o;
    o.inv_h2 = 1.0 / (h_ * h_);
    f->factor = std::make_unique<MeshlessFactor>(problem_, free_, o);
  }
  f->factor->refactor(x);
  f->x = x;
  f->tool_points.clear();
  return f;
}

void ImplicitModel::linearize() {
  // With the contact compliance W = N P^{-1} N^T of the last frame's contacts (contact_correction.hpp), a
  // translation dp of tool o closes its contacts' gaps by n_c . dp; they answer with d lambda = W^{-1} N_o dp
  // while the other contacts hold, so the tissue's force changes by K dp, K = N_o^T W^{-1} N_o
  // (docs/model/24-implicit.md 24.3). P is the factor in use: exact when it was built at this state,
  // otherwise off by its drift.
  const auto& tools = problem_.tools();
  linearization_.assign(tools.size(), std::nullopt);
  const EquilibriumPreconditioner* P =
      factor_ ? static_cast<const EquilibriumPreconditioner*>(factor_->factor.get()) : multigrid_.get();
  // With the tools on the wall's surface the driver estimates the stiffness (a secant along the normal).
  if (P == nullptr || tools.empty() || embedded_) return;
  // The multigrid's solves leave the correction alone (it holds the contacts itself): build it for the
  // hand-off.
  if (multigrid_) newton_.update_contact_correction();
  const ContactCorrection& w = newton_.contact_correction();
  for (std::size_t o = 0; o < tools.size(); ++o) {
    ToolLinearization lin;
    if (w.valid() && !w.nodes().empty()) {
      std::vector<char> mask(w.nodes().size(), 0);
      for (std::size_t c = 0; c < mask.size(); ++c)
        mask[c] =
            contacts_.in_contact(w.nodes()[c]) && contacts_.tool_of(w.nodes()[c]) == static_cast<int>(o);
      lin.stiffness_n_per_m = w.tool_stiffness(mask, x_);
    }
    // The direction the tissue pushes the tool: against the force the tool exerts on it.
    if (loads_[o].force_vector_n.norm() > 0.0) lin.normal = -loads_[o].force_vector_n.normalized();
    if (candidates_) candidates_->fill(o, contacts_, x_, *P, newton_.node_compliance(), lin);
    linearization_[o] = lin;
  }
}

void ImplicitModel::install(std::unique_ptr<Factor> f) {
  spare_ = std::move(factor_);  // the next refactorisation refills it
  factor_ = std::move(f);
  factor_tool_points_ = factor_->tool_points.empty() ? tools_.points(s_) : factor_->tool_points;
  newton_.set_preconditioner(factor_->factor.get());
  ++factorisations_;
}

void ImplicitModel::poll_background() {
  if (pending_.valid() && pending_.wait_for(std::chrono::seconds(0)) == std::future_status::ready)
    install(pending_.get());
}

void ImplicitModel::relinearize_now() {
  if (multigrid_) {
    if (level_pending_.valid()) level_spare_ = multigrid_->install(level_pending_.get());
    level_spare_ = multigrid_->install(multigrid_->build_level(x_, std::move(level_spare_)));
    multigrid_->prepare_window(x_);
    linearize();
    return;
  }
  if (!factor_) return;
  if (pending_.valid()) install(pending_.get());
  auto f = build_factor(x_, std::move(spare_));
  f->tool_points = tools_.points(s_);
  install(std::move(f));
  newton_.update_contact_correction();
  linearize();
}

void ImplicitModel::maybe_refactor(const NewtonResult& r) {
  if (!factor_) return;
  const int cg_per_newton = r.iterations > 0 ? r.cg_iterations / r.iterations : 0;
  bool drifted = cg_per_newton > settings_.refactor_cg_iterations || r.cg_rate > settings_.refactor_cg_rate ||
                 (settings_.refactor_residual > 0.0 && r.residual > settings_.refactor_residual);
  const std::vector<Vec3> points = tools_.points(s_);
  for (std::size_t o = 0; o < points.size(); ++o) {
    // Travel deforms the wall only in contact: a tool moving through the lumen leaves the tangent as it was.
    if (loads_[o].contacts == 0) factor_tool_points_[o] = points[o];
    drifted = drifted || (settings_.refactor_travel > 0.0 &&
                          (points[o] - factor_tool_points_[o]).norm() > settings_.refactor_travel * spacing_);
  }
  if (!drifted || pending_.valid()) return;
  // The job refills the spare factor (no frame uses it) at a copy of the state: the frames go on meanwhile.
  auto job = [this, x = x_, points, reuse = std::move(spare_), background = realtime_]() mutable {
    // In the background this thread alone builds with one thread, so the frames keep the other core; run in
    // line (offline), it must leave the caller's thread count alone (it once set the whole run to one
    // thread).
    if (background) omp_set_num_threads(1);
    auto f = build_factor(x, std::move(reuse));
    f->tool_points = points;
    return f;
  };
  factor_tool_points_ = points;  // no second trigger for the same travel while this one builds
  if (realtime_)
    pending_ = std::async(std::launch::async, std::move(job));
  else
    install(job());
}

void ImplicitModel::poll_multigrid() {
  if (level_pending_.valid() &&
      level_pending_.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
    level_spare_ = multigrid_->install(level_pending_.get());
    ++factorisations_;
    spdlog::debug("implicit: multigrid level installed (built in {:.1f} ms)",
                  multigrid_->last_level_seconds() * 1e3);
  }
}

void ImplicitModel::refresh_multigrid() {
  // The coarse level carries the wall's global response, which the frames change slowly: it is rebuilt every
  // level_refresh_frames frames, in line in a deterministic run, in the background (one thread) in a realtime
  // session, which leaves the second core to the haptic thread between builds.
  if (!multigrid_) return;
  ++frames_since_level_;
  if (realtime_) {
    if (level_pending_.valid() || frames_since_level_ < settings_.level_refresh_frames) return;
    auto job = [this, x = x_, reuse = std::move(level_spare_)]() mutable {
      omp_set_num_threads(1);
      return multigrid_->build_level(x, std::move(reuse));
    };
    level_pending_ = std::async(std::launch::async, std::move(job));
    frames_since_level_ = 0;
  } else if (frames_since_level_ >= settings_.level_refresh_frames) {
    level_spare_ = multigrid_->install(multigrid_->build_level(x_, std::move(level_spare_)));
    ++factorisations_;
    frames_since_level_ = 0;
  }
}

void ImplicitModel::approach_tools(double s, const Vec3Array& f_ext) {
  if (!embedded_ || tool_step_spacings() > 0.0) return;
  const double inf = std::numeric_limits<double>::infinity();
  double total = 0.0;
  for (std::size_t o = 0; o < tools_.size(); ++o) total = std::max(total, tools_.distance_to_target(o));
  // At most kMaxCarriedSteps steps (the last one the frame's own first Newton step): a frame that came late
  // must not spend longer on a longer way, or every frame after it comes later still.
  const double step = std::max(settings_.contact_substep * spacing_, total / kMaxCarriedSteps);
  const long long substeps_before = substeps_;
  double far = 0.0;
  for (;;) {
    far = 0.0;
    for (std::size_t o = 0; o < tools_.size(); ++o) far = std::max(far, tools_.distance_to_target(o));
    if (!(settings_.contact_substep > 0.0) || far <= step * (1.0 + 1e-9)) break;
    // Every tool a step's fraction of its way, so that they arrive together.
    for (std::size_t o = 0; o < tools_.size(); ++o)
      tools_.advance(o, step / far * tools_.distance_to_target(o));
    place_tools(s);
    // The samples it left are held up to this step's length (the length moved since their linearisation).
    embedded_->set_carried_gap(step);
    embedded_->relinearize_carried(x_);
    if (multigrid_) multigrid_->prepare_window(x_);
    const NewtonResult r = newton_.solve(x_, s, f_ext, InertiaTerm{1.0 / (h_ * h_), &anchor_},
                                         SteadyClock::time_point::max(), true, 1);
    cg_total_ += r.cg_iterations;
    ++substeps_;
  }
  // The frame's own carried step answers what remains of the way.
  if (substeps_ != substeps_before) embedded_->set_carried_gap(far);
  for (std::size_t o = 0; o < tools_.size(); ++o) tools_.advance(o, inf);
}

bool ImplicitModel::thrown_off() const {
  // A wall whose force residual exceeds a thousand times E dx^2 (the force that strains a node's
  // neighbourhood by 100 %; 11 N on the real-time vein, whose tool force is about 10 mN) is far from any
  // equilibrium the frames can reach: frames that kept up with a hand reached at most 157 times it (the
  // carried steps' penalty forces), frames that diverged passed 10^3 a frame or two before their state
  // became non-finite (a wandering hand, frames of one Newton step 0.2 s apart, in lockstep).
  constexpr double kThrownOff = 1e3;
  const double scale = problem_.discretization().material().youngs_modulus_pa * spacing_ * spacing_;
  const Vec3Array& r = newton_.last_residual();
  double r2 = 0.0;
  for (Index i : free_.nodes) {
    const auto k = static_cast<std::size_t>(i);
    if (!x_[k].allFinite()) return true;
    if (k < r.size()) r2 += r[k].squaredNorm();
  }
  return !(std::sqrt(r2) <= kThrownOff * scale);
}

void ImplicitModel::recover() {
  // Back to the last frame that handed on, its tools where they were then: the next frames carry them to the
  // device's poses from there. The hand keeps feeling that frame's force meanwhile.
  if (recoveries_++ == 0)
    spdlog::warn(
        "implicit: frame {} (t = {:.3g} s) threw the wall off its equilibria (a hand faster than the frames "
        "follow): back to the last frame that handed on its force, the tool behind the hand until the frames "
        "catch up (summary.json counts such frames: frames_thrown_off)",
        frames_, t_ + h_);
  catching_up_ = true;
  x_ = safe_->x;
  std::fill(v_.begin(), v_.end(), Vec3::Zero());
  tools_.restore(safe_->tools);
  frame_tool_points_ = safe_->frame_tool_points;
  frame_tool_move_.assign(frame_tool_points_.size(), Vec3::Zero());
  place_tools(s_);
  embedded_->linearize(x_);
}

bool ImplicitModel::penalty_agrees(const std::vector<ObstacleLoad>& penalty,
                                   const std::vector<ObstacleLoad>& wall) const {
  // A residual relative to the largest force in play is no measure of a wall that the tools crush: there
  // the penalty's force sets that scale. Frames that kept up with a hand had the two forces within a factor
  // of 0.94-2.3 of each other; frames too short for their carried steps (time_budget_s 6 ms on the
  // real-time vein) handed on walls whose penalty carried 2-42 N against their own 0.3-0.5 N, a hundred
  // times the continuum's 3-7 mN. Forces below a hundredth of E dx^2 are the contact's onset: no check.
  const double negligible =
      1e-2 * problem_.discretization().material().youngs_modulus_pa * spacing_ * spacing_;
  for (std::size_t o = 0; o < penalty.size() && o < wall.size(); ++o) {
    const double p = penalty[o].force_vector_n.norm(), w = wall[o].force_vector_n.norm();
    if (std::max(p, w) > negligible && !(std::min(p, w) >= kPenaltyAgreement * std::max(p, w))) return false;
  }
  return true;
}

double ImplicitModel::tool_step_spacings() const {
  // After a frame that threw the wall off, the tools catch up with the device in steps of kCatchUpStep
  // node spacings, one after each frame that handed on (a hand held past a frame's reach would otherwise
  // throw the wall off again at every frame; steps taken at every frame outran a wall whose frames were
  // one Newton step each, and its far-off states became the ones to go back to).
  return settings_.max_tool_step > 0.0 ? settings_.max_tool_step : catching_up_ ? kCatchUpStep : 0.0;
}

std::vector<Vec3> ImplicitModel::frame_goal_points(double s) const {
  // With max_tool_step, or while catching up after a frame thrown off, the tools were already moved their
  // bounded step (advance_tools); otherwise the frame takes them to the device's poses.
  return tool_step_spacings() > 0.0 ? tools_.points(s) : tools_.target_points(s);
}

bool ImplicitModel::warm_start_from_motion(const std::vector<Vec3>& targets) {
  // The wall's response to a tool's move is nearly linear over a frame: the last frame's motion m, scaled by
  // the projection c of this frame's move d onto the last one's d', predicts this frame's. It applies only
  // when that motion joined two states near equilibrium (otherwise it carries the solver's corrections), and
  // when d runs along d' (a turn, from pressing to sliding, would be predicted by the wrong motion).
  if (!(settings_.warm_start_residual > 0.0) || !motion_trusted_ || last_motion_.size() != x_.size() ||
      last_tool_move_.size() != tools_.size() || frame_tool_points_.size() != tools_.size())
    return false;
  double dd = 0.0, dd_last = 0.0, d_last2 = 0.0;
  for (std::size_t o = 0; o < tools_.size(); ++o) {
    const Vec3 d = targets[o] - frame_tool_points_[o];
    dd += d.squaredNorm();
    dd_last += d.dot(last_tool_move_[o]);
    d_last2 += last_tool_move_[o].squaredNorm();
  }
  // (A hundredth of a node spacing is no move, as for tools_moved_.)
  const double still = 1e-4 * spacing_ * spacing_;
  if (d_last2 <= still || dd <= still) return false;
  const double c = dd_last / d_last2;
  // |d - c d'|^2 = |d|^2 - c^2 |d'|^2: the part of the move the last motion does not predict, at most a fifth
  // of it; and at most twice the last move (a longer extrapolation leaves the linear range).
  if (!(c > 0.0 && c <= 2.0) || dd - c * c * d_last2 > 0.04 * dd) return false;
  // A tool in contact that moves more along the wall than into it (a slide, |tangential| > |d| / 2) has its
  // dent carried along instead (advect_with_tools): a slide's last motion is mostly the correction of its
  // frame's start, and extrapolated it leaves the wall off the tool (in realtime sessions on the real-time
  // vein, every such frame ended with no sample in contact).
  for (std::size_t o = 0; o < tools_.size(); ++o)
    if (const auto T = move_along_wall(o, targets))
      if (T->squaredNorm() > 0.25 * (targets[o] - frame_tool_points_[o]).squaredNorm()) return false;
  if (!(tool_step_spacings() > 0.0))
    for (std::size_t o = 0; o < tools_.size(); ++o)
      tools_.advance(o, std::numeric_limits<double>::infinity());
  for (Index i : free_.nodes) x_[i] += c * last_motion_[i];
  ++warm_started_frames_;
  return true;
}

std::optional<Vec3> ImplicitModel::move_along_wall(std::size_t o, const std::vector<Vec3>& targets) const {
  // Along the wall: perpendicular to the force the tool last handed on.
  const Vec3 f = loads_[o].force_vector_n;
  if (loads_[o].contacts == 0 || !(f.norm() > 0.0)) return std::nullopt;
  const Vec3 n = f.normalized();
  const Vec3 d = targets[o] - frame_tool_points_[o];
  return Vec3(d - n.dot(d) * n);
}

void ImplicitModel::advect_with_tools(const std::vector<Vec3>& targets) {
  // A tool sliding along the wall carries its dent with it: the displacement field moves by the tool's move
  // T along the wall, u'(X) = u(X - T), to first order x_i - (F_i - I) T.
  if (frame_tool_points_.size() != tools_.size()) return;
  int in_contact = 0;
  Vec3 T = Vec3::Zero();
  for (std::size_t o = 0; o < tools_.size(); ++o)
    if (const auto along = move_along_wall(o, targets)) ++in_contact, T = *along;
  if (in_contact != 1 || T.norm() <= 1e-2 * spacing_) return;
  const Vec3Array x = x_;
  const Discretization& disc = problem_.discretization();
  for (Index i : free_.nodes) x_[i] = x[i] - (disc.deformation_gradient(i, x) - Mat3::Identity()) * T;
  ++advected_frames_;
}

void ImplicitModel::prepare_frame(double s, const Vec3Array& f_ext) {
  // The inertia's anchor a = x_n + h v_n, prescribed nodes at their positions at s, the tools placed.
  const Index n = problem_.discretization().num_nodes();
  const std::vector<Vec3> before = tools_.points(s_);
  x_old_ = x_;
  anchor_.resize(x_.size());
  for (Index i = 0; i < n; ++i) {
    anchor_[i] = x_[i] + h_ * v_[i];
    // Tools on the wall's surface: the frame starts from x_n (the carried first step answers the tools'
    // move); at the nodes, from the inertial prediction, the nodes the tools entered projected onto their
    // surfaces.
    x_[i] = problem_.constrained()[i] ? problem_.prescribed_position(i, s) : embedded_ ? x_[i] : anchor_[i];
  }
  if (embedded_) {
    // The carried step holds the samples the tools left by up to their move (EmbeddedContact).
    const std::vector<Vec3> targets = frame_goal_points(s);
    double move = 0.0;
    if (frame_tool_points_.size() == targets.size())
      for (std::size_t o = 0; o < targets.size(); ++o)
        move = std::max(move, (targets[o] - frame_tool_points_[o]).norm());
    embedded_->set_carried_gap(move);
    warm_started_ = warm_start_from_motion(targets);
    if (!warm_started_) advect_with_tools(targets);
  } else {
    warm_started_ = false;
  }
  if (!warm_started_) approach_tools(s, f_ext);
  place_tools(s);
  const std::vector<Vec3> previous = frame_tool_points_;
  frame_tool_points_ = tools_.points(s);
  frame_tool_move_.assign(frame_tool_points_.size(), Vec3::Zero());
  if (previous.size() == frame_tool_points_.size())
    for (std::size_t o = 0; o < previous.size(); ++o)
      frame_tool_move_[o] = frame_tool_points_[o] - previous[o];
  contacts_.project(x_, true);
  // (A hundredth of a node spacing is no move: a hand held still jitters by less.)
  tools_moved_ = false;
  const std::vector<Vec3> after = tools_.points(s);
  for (std::size_t o = 0; o < after.size(); ++o)
    tools_moved_ = tools_moved_ || (after[o] - before[o]).norm() > 1e-2 * spacing_;
  // The window is formed at the contact set the frame's first Newton step solves with: the carried one when
  // the tools moved and the frame was not warm-started (NewtonEquilibrium::solve), else every sample there.
  if (embedded_) {
    if (tools_moved_ && !warm_started_)
      embedded_->relinearize_carried(x_);
    else
      embedded_->linearize(x_);
  }
  if (multigrid_) multigrid_->prepare_window(x_);
}

StepReport ImplicitModel::step() {
  const Stopwatch frame;
  poll_background();
  poll_multigrid();
  const double t_next = t_ + h_;
  const double s_next = ramped_load_factor(t_next, settings_.ramp_time_s);
  Vec3Array f_ext;
  problem_.external_forces(s_next, f_ext);
  if (settings_.max_tool_step > 0.0)
    advance_tools(settings_.max_tool_step);
  else if (catching_up_)
    advance_tools(last_handoff_ ? kCatchUpStep : 0.0);
  else if (realtime_ && !embedded_ && settings_.realtime_tool_step > 0.0)
    advance_tools(last_handoff_ ? settings_.realtime_tool_step : 0.0);
  NewtonResult r;
  bool failed = false;
  Stopwatch phase;
  try {
    prepare_frame(s_next, f_ext);
    const auto deadline =
        realtime_ && settings_.time_budget_s > 0.0
            ? SteadyClock::now() + std::chrono::duration_cast<SteadyClock::duration>(
                                       std::chrono::duration<double>(settings_.time_budget_s))
            : SteadyClock::time_point::max();
    phase.restart();
    r = newton_.solve(x_, s_next, f_ext, InertiaTerm{1.0 / (h_ * h_), &anchor_}, deadline,
                      tools_moved_ && !warm_started_);
  } catch (const NumericalError& e) {
    if (!safe_) throw;
    spdlog::debug("implicit: frame {}: {}", frames_, e.what());
    failed = true;
  }
  split_.solve_s += phase.seconds();
  const bool recovered = safe_ && (failed || thrown_off());
  if (recovered) {
    recover();
    r = NewtonResult{};
    r.residual = safe_->residual;
  }
  // The velocity of a frame that ended unconverged is partly the solver's correction, not motion: carried
  // into the next frame's start x + h v it would add that correction again, and frames the budget stops
  // then drift further from their equilibrium each time (on the real-time vein under a random hand, from a
  // relative residual of 0.4 at the first contact to 10^2 within a second).
  for (std::size_t i = 0; i < x_.size(); ++i)
    v_[i] = r.converged ? Vec3((x_[i] - x_old_[i]) / h_) : Vec3::Zero();
  // This frame's motion predicts the next one's when it started and ended near an equilibrium.
  const bool near_equilibrium = !recovered && (r.converged || r.residual <= settings_.warm_start_residual);
  motion_trusted_ = near_equilibrium && start_near_equilibrium_;
  start_near_equilibrium_ = near_equilibrium;
  last_motion_.resize(x_.size());
  for (std::size_t i = 0; i < x_.size(); ++i) last_motion_[i] = x_[i] - x_old_[i];
  last_tool_move_ = frame_tool_move_;
  // The frame's loads are handed on when the frame is near enough its equilibrium, with no contact that pulls
  // (held, such a contact makes the pushing ones carry more: +128 % measured at a residual of 6e-3);
  // otherwise the last one that was keeps serving with its own tool pose (contact reactions far from
  // equilibrium are not a force). With the tools on the wall's surface the frame before must have ended
  // below the threshold too: a frame that starts from a wall thrown far off (a residual of 18 under a 5 mm/s
  // slide) can end below it with hundreds of samples in the tool, whose penalty sets the residual's scale.
  // (A frame that went back to the last one that handed on hands on nothing new.)
  bool handoff = !recovered &&
                 (r.converged || (r.residual <= settings_.handoff_max_residual && contacts_.pulling() == 0) ||
                  (embedded_ && r.residual <= settings_.handoff_surface_residual &&
                   (frames_ == 0 || last_residual_ <= settings_.handoff_surface_residual)));
  const std::vector<Vec3> tool_points = tools_.points(s_next);
  std::vector<ObstacleLoad> wall_answer;
  if (handoff && embedded_) {
    // The wall's answer to the contact, not the penalty's (EmbeddedContact::reaction_loads): the residual
    // of the solve's last evaluation, at this very state and contact set.
    embedded_->linearize(x_);
    wall_answer = embedded_->reaction_loads(tool_points, x_, newton_.last_residual(), problem_.constrained());
    if (!r.converged && !penalty_agrees(embedded_->loads(tool_points), wall_answer)) {
      handoff = false;
      ++disagreements_;
    }
  }
  if (handoff) {
    if (!contacts_.empty()) loads_ = contacts_.loads(newton_.last_residual(), x_, tool_points);
    if (embedded_) loads_ = std::move(wall_answer);
    handoff_points_ = tool_points;
    if (embedded_) safe_ = SafeState{x_, tools_.placed(), frame_tool_points_, r.residual};
  } else {
    ++stale_handoffs_;
  }
  last_handoff_ = handoff;
  if (catching_up_ && handoff) {
    // Caught up once the device is within kMaxCarriedSteps catch-up steps of a wall that handed on (the
    // frame's carried steps take the rest).
    double behind = 0.0;
    for (std::size_t o = 0; o < tools_.size(); ++o) behind = std::max(behind, tools_.distance_to_target(o));
    catching_up_ = behind > kMaxCarriedSteps * kCatchUpStep * spacing_;
  }
  t_ = t_next;
  s_ = s_next;
  for (const auto& p : x_)
    if (!p.allFinite())
      throw NumericalError(fmt::format("implicit: the state became non-finite at t = {:.6g} s", t_));
  ++frames_;
  newton_total_ += r.iterations;
  cg_total_ += r.cg_iterations;
  out_of_time_ += r.out_of_time ? 1 : 0;
  unconverged_ += r.converged ? 0 : 1;
  last_residual_ = r.residual;
  worst_residual_ = std::max(worst_residual_, r.residual);
  phase.restart();
  maybe_refactor(r);
  refresh_multigrid();
  split_.refactor_s += phase.seconds();
  phase.restart();
  if (handoff) linearize();
  split_.linearize_s += phase.seconds();
  split_.frame_s += frame.seconds();
  StepReport rep;
  rep.time_s = t_;
  rep.load_factor = s_;
  rep.iterations = r.iterations;
  rep.inner_iterations = r.cg_iterations;
  rep.residual = r.residual;
  rep.converged = r.converged;
  return rep;
}

StepReport ImplicitModel::advance(int k) {
  const double t_end = std::min(k * settings_.output_interval_s, settings_.duration_s);
  StepReport r, sum;
  sum.converged = true;
  while (t_ < t_end - 0.5 * h_) {
    r = step();
    sum.iterations += r.iterations;
    sum.inner_iterations += r.inner_iterations;
    sum.residual = std::max(sum.residual, r.residual);
    sum.converged = sum.converged && r.converged;
  }
  sum.time_s = t_;
  sum.load_factor = s_;
  return sum;
}

std::optional<ToolLinearization> ImplicitModel::tool_linearization(std::size_t tool) const {
  return tool < linearization_.size() ? linearization_[tool] : std::nullopt;
}

nlohmann::json ImplicitModel::info() const {
  nlohmann::json j = {{"model", "implicit"},
                      {"frame_s", h_},
                      {"frames", frames_},
                      {"rel_tolerance", settings_.rel_tolerance},
                      {"newton_iterations", newton_total_},
                      {"cg_iterations", cg_total_},
                      {"frames_out_of_time", out_of_time_},
                      {"frames_not_converged", unconverged_},
                      {"last_residual", last_residual_},
                      {"worst_residual", worst_residual_},
                      {"factorisations", factorisations_},
                      {"max_tool_lag_m", max_tool_lag_},
                      {"frames_handing_on_an_older_force", stale_handoffs_},
                      {"contact_substeps", substeps_},
                      {"warm_started_frames", warm_started_frames_},
                      {"advected_frames", advected_frames_},
                      {"frames_thrown_off", recoveries_},
                      {"frames_penalty_and_wall_disagreed", disagreements_},
                      {"force_evaluations", newton_.force_evaluations()},
                      {"force_evaluations_reused", newton_.force_evaluations_reused()},
                      {"forces_precision", newton_.float_forces() ? "float" : "double"},
                      {"handoff_max_residual", settings_.handoff_max_residual},
                      {"max_forcing", newton_.settings().max_forcing},
                      {"far_forcing", newton_.settings().far_forcing},
                      {"time_budget_s", settings_.time_budget_s},
                      {"duration_s", settings_.duration_s},
                      {"ramp_time_s", settings_.ramp_time_s},
                      {"output_interval_s", settings_.output_interval_s}};
  // Where a frame's wall time goes, seconds summed over the frames: the Newton-PCG solve, the synchronous
  // refactorisations (lockstep; a realtime session builds them in the background), the tools' linearisation
  // for the haptic thread (its compliance solves), and the whole frame.
  j["wall_time_s"] = {{"frames", split_.frame_s},
                      {"solve", split_.solve_s},
                      {"refactor", split_.refactor_s},
                      {"linearize", split_.linearize_s}};
  j["preconditioner"] = factor_ ? factor_->factor->info() : multigrid_ ? multigrid_->info() : tet_->info();
  return j;
}

}  // namespace vascsim
