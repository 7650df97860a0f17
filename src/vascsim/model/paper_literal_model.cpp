#include "vascsim/model/paper_literal_model.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <algorithm>
#include <cmath>
#include <utility>

#include "vascsim/constraints/distance_constraint.hpp"
#include "vascsim/constraints/energy_constraint.hpp"
#include "vascsim/constraints/xpbd_projection.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/core/parallel.hpp"
#include "vascsim/geometry/boundary.hpp"
#include "vascsim/model/stability.hpp"

namespace vascsim {

namespace {

constexpr int kPowerIterations = 60;  // as ExplicitModel

// The paper's pipeline: literal strain, no stabiliser, no volume term (docs/model/19-position-based.md
// section 19.5 step 1).
EnergyOptions literal_energy_options() {
  EnergyOptions o;
  o.strain = StrainMeasure::MuellerNoHalf;
  o.volume_stiffness_pa = 0.0;
  o.stabilizer_alpha = 0.0;
  return o;
}

// Unordered node pairs (i < j), sorted, each once.
std::vector<std::pair<Index, Index>> unique_pairs(std::vector<std::pair<Index, Index>> pairs) {
  for (auto& [a, b] : pairs)
    if (a > b) std::swap(a, b);
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

std::vector<std::pair<Index, Index>> stretch_pairs(const Discretization& disc, StretchPairs which) {
  std::vector<std::pair<Index, Index>> pairs;
  if (which == StretchPairs::TetEdges) {
    for (const Edge& e : tet_edges(disc.tets())) pairs.emplace_back(e[0], e[1]);
    return pairs;
  }
  // Per-node support radii may make N_i asymmetric: the union of both directions, once.
  const PairTable& pt = disc.pairs();
  pairs.reserve(pt.col.size());
  for (Index i = 0; i + 1 < static_cast<Index>(pt.row_start.size()); ++i)
    for (Index k = pt.row_start[i]; k < pt.row_start[i + 1]; ++k) pairs.emplace_back(i, pt.col[k]);
  return unique_pairs(std::move(pairs));
}

}  // namespace

// The literal energy lives here (not in the scene's Problem, whose energy follows the scene's `energy`
// block), with a Problem of its own so the stability estimate of stability.hpp sees the literal forces.
struct PaperLiteralModel::Impl {
  explicit Impl(const Problem& problem)
      : energy(problem.discretization(), literal_energy_options()),
        literal_problem(energy, problem.regions(), problem.gravity()) {}
  PointPrimitiveEnergy energy;
  Problem literal_problem;
};

PaperLiteralModel::~PaperLiteralModel() = default;

PaperLiteralSettings read_paper_literal_settings(JsonReader& pl) {
  const PaperLiteralSettings d;  // the defaults live in one place (the settings struct)
  PaperLiteralSettings s;
  const TimeSchedule schedule = read_time_schedule(pl, {d.duration_s, d.ramp_time_s, d.output_interval_s});
  s.duration_s = schedule.duration_s;
  s.ramp_time_s = schedule.ramp_time_s;
  s.output_interval_s = schedule.output_interval_s;
  s.step_s = pl.number("step_s", d.step_s, 1e-9, 1.0);
  check_step_count(pl, schedule, s.step_s, "step_s");
  s.iterations = pl.integer("iterations", d.iterations, 1, 1000);
  s.stretch_stiffness = pl.number("stretch_stiffness", d.stretch_stiffness, 0.0, 1.0);
  s.energy_stiffness = pl.number("energy_stiffness", d.energy_stiffness, 0.0, 1.0);
  s.stretch_pairs = pl.string("stretch_pairs", "tet_edges", {"tet_edges", "neighbours"}) == "tet_edges"
                        ? StretchPairs::TetEdges
                        : StretchPairs::Neighbours;
  s.damping_per_s = pl.number("damping_per_s", d.damping_per_s, 0.0, 1e6);
  pl.finish();
  return s;
}

ModelEntry paper_literal_model_entry() {
  ModelEntry e;
  e.name = "paper_literal";
  e.summary = "the paper's pipeline as printed (explicit step + PBD constraints), for reproduction";
  e.capabilities = {.dynamic = true,
                    .takes_tools = false,
                    .device_driven = false,
                    .releases_regions = false,
                    .quadratic_basis = false};
  e.read_settings = [](JsonReader& block) { return std::any(read_paper_literal_settings(block)); };
  e.make = [](const Problem& problem, const std::any& settings) -> std::unique_ptr<Model> {
    return std::make_unique<PaperLiteralModel>(problem, settings_as<PaperLiteralSettings>(settings));
  };
  e.schedule = [](const std::any& settings) {
    const auto& s = settings_as<PaperLiteralSettings>(settings);
    return TimeSchedule{s.duration_s, s.ramp_time_s, s.output_interval_s};
  };
  e.law_restriction = [](const std::any&, const std::string& law) -> std::string {
    if (law == "svk") return "";
    return fmt::format("the paper_literal model is the paper's SVK; '{}' needs another model", law);
  };
  return e;
}

PaperLiteralModel::PaperLiteralModel(const Problem& problem, const PaperLiteralSettings& s)
    : problem_(problem), settings_(s) {
  if (!(s.duration_s > 0.0)) throw InputError("paper_literal: duration_s must be > 0");
  if (!(s.output_interval_s > 0.0)) throw InputError("paper_literal: output_interval_s must be > 0");
  if (!(s.ramp_time_s >= 0.0)) throw InputError("paper_literal: ramp_time_s must be >= 0");
  if (!(s.step_s > 0.0)) throw InputError("paper_literal: step_s must be > 0");
  if (s.iterations < 1) throw InputError("paper_literal: iterations must be >= 1");
  if (!(s.stretch_stiffness >= 0.0 && s.stretch_stiffness <= 1.0))
    throw InputError("paper_literal: stretch_stiffness must be in [0, 1]");
  if (!(s.energy_stiffness >= 0.0 && s.energy_stiffness <= 1.0))
    throw InputError("paper_literal: energy_stiffness must be in [0, 1]");
  if (!(s.damping_per_s >= 0.0)) throw InputError("paper_literal: damping_per_s must be >= 0");

  const Discretization& disc = problem.discretization();
  const Index n = disc.num_nodes();
  impl_ = std::make_unique<Impl>(problem);
  spdlog::info(
      "paper_literal: meshless forces use the literal strain eps = F^T F - I (Eq. 5, 4x stiffer than "
      "E = {:.4g} Pa) with no stabiliser and no volume term, whatever the scene's energy block says; "
      "volumes from the scene's discretisation",
      disc.material().youngs_modulus_pa);

  x_ = disc.rest_positions();
  v_.assign(x_.size(), Vec3::Zero());
  p_ = x_;
  f_constraint_.assign(x_.size(), Vec3::Zero());
  inv_mass_.resize(x_.size());
  for (Index i = 0; i < n; ++i) inv_mass_[i] = problem.constrained()[i] ? 0.0 : 1.0 / disc.masses()[i];

  // Stretching constraints (Eq. 13) at their rest lengths; pairs of two prescribed nodes never move.
  for (const auto& [a, b] : stretch_pairs(disc, s.stretch_pairs)) {
    if (inv_mass_[a] == 0.0 && inv_mass_[b] == 0.0) continue;
    stretch_nodes_.push_back(a);
    stretch_nodes_.push_back(b);
    stretch_rest_.push_back((x_[a] - x_[b]).norm());
  }
  // Energy constraints (Eq. 18) of every virtual tetrahedron, springs calibrated on dilation.
  const double kappa = disc.material().bulk_modulus();
  const auto& tets = disc.tets();
  tet_k_.resize(tets.size());
  tet_rest_.resize(tets.size());
  const auto springs = constraints::barycentre_springs_of_mesh(x_, tets, disc.masses(), kappa);
  for (std::size_t t = 0; t < tets.size(); ++t) {
    tet_rest_[t] = springs[t].rest_distances;
    tet_k_[t] = springs[t].stiffness;
  }
  ks_prime_ = constraints::pbd_iteration_stiffness(s.stretch_stiffness, s.iterations);
  ke_prime_ = constraints::pbd_iteration_stiffness(s.energy_stiffness, s.iterations);

  // Whole steps per output interval, so output times are exact.
  const TimeSchedule schedule{s.duration_s, s.ramp_time_s, s.output_interval_s};
  const long long per_output = whole_steps_per_output(schedule, s.step_s, "paper_literal.step_s");
  dt_ = s.output_interval_s / static_cast<double>(per_output);
  num_steps_ = output_count(schedule);

  // docs/model/19-position-based.md section 19.5: report the explicit limit of the literal forces; above it
  // only PBD keeps the run bounded.
  int power_its = 0;
  const double omega = max_angular_frequency(impl_->literal_problem, x_, kPowerIterations, 1e-4, &power_its);
  dt_explicit_ = omega > 0.0 ? 2.0 / (1.05 * omega) : INFINITY;
  spdlog::info(
      "paper_literal: {} stretching constraints ({}), {} energy constraints; dt = {:.4g} s, {} PBD "
      "iterations, k_s = {} (k_s' = {:.4g}), k_e = {} (k_e' = {:.4g}), damping {} 1/s; {} steps per "
      "output, {} outputs",
      stretch_rest_.size(), s.stretch_pairs == StretchPairs::TetEdges ? "tet edges" : "neighbour pairs",
      tet_k_.size(), dt_, s.iterations, s.stretch_stiffness, ks_prime_, s.energy_stiffness, ke_prime_,
      s.damping_per_s, per_output, num_steps_);
  spdlog::info(
      "paper_literal: explicit stability limit of the literal forces 2/(1.05 omega_max) = {:.4g} s "
      "({} power iterations)",
      dt_explicit_, power_its);
  if (dt_ > dt_explicit_)
    spdlog::warn(
        "paper_literal: dt = {:.3g} s is {:.3g}x the explicit stability limit {:.3g} s of the literal "
        "forces; only the PBD constraints can keep the run bounded, and their stiffness depends on dt, "
        "n and k (docs/model/19-position-based.md section 19.5)",
        dt_, dt_ / dt_explicit_, dt_explicit_);
}

double PaperLiteralModel::load_factor_at(double t) const {
  return ramped_load_factor(t, settings_.ramp_time_s);
}

void PaperLiteralModel::project_stretch(std::size_t c) {
  const Index a = stretch_nodes_[2 * c], b = stretch_nodes_[2 * c + 1];
  const auto con = constraints::distance_constraint(p_[a], p_[b], stretch_rest_[c]);
  std::array<Vec3, 2> dp;
  const double sc = constraints::pbd_project(con, {inv_mass_[a], inv_mass_[b]}, ks_prime_, dp);
  p_[a] += dp[0];
  p_[b] += dp[1];
  const double scale = sc / (dt_ * dt_);
  f_constraint_[a] += scale * con.grad[0];
  f_constraint_[b] += scale * con.grad[1];
}

void PaperLiteralModel::project_energy(std::size_t t) {
  const Tet& tet = problem_.discretization().tets()[t];
  const auto& masses = problem_.discretization().masses();
  constraints::TetPositions x;
  constraints::TetMasses m;
  std::array<double, 4> w;
  for (int a = 0; a < 4; ++a) {
    x[a] = p_[tet[a]];
    m[a] = masses[tet[a]];
    w[a] = inv_mass_[tet[a]];
  }
  const double k = tet_k_[t];
  const auto con = constraints::literal_energy_constraint(x, m, {k, k, k, k}, tet_rest_[t]);
  std::array<Vec3, 4> dp;
  const double sc = constraints::pbd_project(con, w, ke_prime_, dp);
  const double scale = sc / (dt_ * dt_);
  for (int a = 0; a < 4; ++a) {
    p_[tet[a]] += dp[a];
    f_constraint_[tet[a]] += scale * con.grad[a];
  }
}

void PaperLiteralModel::step(double s_next) {
  const Index n = static_cast<Index>(x_.size());
  const auto& m = problem_.discretization().masses();
  const auto& fixed = problem_.constrained();
  const double dt = dt_;
  impl_->energy.forces(x_, f_int_, false);
  problem_.external_forces(s_next, f_ext_);
#pragma omp parallel for schedule(static) if (n >= kParallelMinNodes)
  for (Index i = 0; i < n; ++i) {
    f_constraint_[i] = f_int_[i];
    if (fixed[i]) {
      p_[i] = problem_.prescribed_position(i, s_next);
    } else {
      v_[i] += (dt / m[i]) * (f_ext_[i] + f_int_[i]);
      p_[i] = x_[i] + dt * v_[i];
    }
  }
  // Serial Gauss-Seidel in a fixed order: the literal pipeline (no colouring, no parallelism).
  for (int it = 0; it < settings_.iterations; ++it) {
    for (std::size_t c = 0; c < stretch_rest_.size(); ++c) project_stretch(c);
    for (std::size_t t = 0; t < tet_k_.size(); ++t) project_energy(t);
  }
  const double decay = std::exp(-settings_.damping_per_s * dt);
#pragma omp parallel for schedule(static) if (n >= kParallelMinNodes)
  for (Index i = 0; i < n; ++i) {
    v_[i] = (p_[i] - x_[i]) * (decay / dt);
    x_[i] = p_[i];
  }
  ++steps_done_;
}

StepReport PaperLiteralModel::advance(int k) {
  const double t_end = std::min(k * settings_.output_interval_s, settings_.duration_s);
  const Vec3Array& X = problem_.discretization().rest_positions();
  // A displacement beyond 10x the body's extent is divergence, even while it is still finite.
  Vec3 lo = X.front(), hi = X.front();
  for (const Vec3& p : X) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double bound2 = std::pow(10.0 * (hi - lo).norm(), 2);
  StepReport r;
  while (t_ < t_end - 0.5 * dt_) {
    t_ += dt_;
    step(load_factor_at(t_));
    ++r.iterations;
    bool ok = true;
    for (std::size_t i = 0; i < x_.size() && ok; ++i)
      ok = x_[i].allFinite() && (x_[i] - X[i]).squaredNorm() < bound2;
    if (!ok)
      throw NumericalError(fmt::format(
          "paper_literal: diverged at step {} (t = {:.6g} s, dt = {:.4g} s; explicit limit {:.4g} s): the "
          "state "
          "became non-finite or moved more than 10x the body size; use a smaller step_s, more iterations or "
          "higher stiffness",
          steps_done_, t_, dt_, dt_explicit_));
  }
  s_ = load_factor_at(t_);
  r.time_s = t_;
  r.load_factor = s_;
  return r;
}

nlohmann::json PaperLiteralModel::info() const {
  return {{"model", "paper_literal"},
          {"strain", "mueller_no_half"},
          {"stabilizer_alpha", 0.0},
          {"step_s", dt_},
          {"explicit_stability_limit_s", dt_explicit_},
          {"iterations", settings_.iterations},
          {"stretch_stiffness", settings_.stretch_stiffness},
          {"stretch_iteration_stiffness", ks_prime_},
          {"energy_stiffness", settings_.energy_stiffness},
          {"energy_iteration_stiffness", ke_prime_},
          {"stretch_pairs", settings_.stretch_pairs == StretchPairs::TetEdges ? "tet_edges" : "neighbours"},
          {"stretch_constraints", stretch_rest_.size()},
          {"energy_constraints", tet_k_.size()},
          {"damping_per_s", settings_.damping_per_s},
          {"steps", steps_done_},
          {"duration_s", settings_.duration_s},
          {"ramp_time_s", settings_.ramp_time_s},
          {"output_interval_s", settings_.output_interval_s}};
}

}  // namespace vascsim
