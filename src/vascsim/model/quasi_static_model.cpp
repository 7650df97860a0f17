#include "vascsim/model/quasi_static_model.hpp"

#include <cmath>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "vascsim/core/error.hpp"
#include "vascsim/model/tet_stiffness.hpp"

namespace vascsim {

namespace {
double dot(const Vec3Array& a, const Vec3Array& b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += a[i].dot(b[i]);
  return s;
}
}  // namespace

QuasiStaticSettings read_quasi_static_settings(JsonReader& qs) {
  QuasiStaticSettings s;
  s.load_steps = qs.integer("load_steps", 10, 1, 100000);
  s.rel_tolerance = qs.number("rel_tolerance", 1e-8, 1e-14, 0.1);
  s.max_newton_iterations = qs.integer("max_newton_iterations", 60, 1, 10000);
  s.max_cg_iterations = qs.integer("max_cg_iterations", 2000, 1, 1000000);
  s.preconditioner = qs.string("preconditioner", "auto", {"auto", "incomplete_cholesky", "cholesky", "none"});
  s.frame_s = qs.number("frame_s", 1e-3, 1e-6, 10.0);
  qs.finish();
  return s;
}

ModelEntry quasi_static_model_entry() {
  ModelEntry e;
  e.name = "quasi_static";
  e.summary = "static equilibrium by Newton-CG at every load step: force-displacement experiments, validation";
  e.capabilities = {.dynamic = false, .takes_tools = true, .device_driven = true, .releases_regions = false};
  e.read_settings = [](JsonReader& block) { return std::any(read_quasi_static_settings(block)); };
  e.make = [](const Problem& problem, const std::any& settings) -> std::unique_ptr<Model> {
    return std::make_unique<QuasiStaticModel>(problem, settings_as<QuasiStaticSettings>(settings));
  };
  return e;
}

QuasiStaticModel::QuasiStaticModel(const Problem& problem, const QuasiStaticSettings& settings)
    : problem_(problem), settings_(settings), x_(problem.discretization().rest_positions()) {
  if (settings.load_steps < 1) throw InputError("quasi_static: load_steps must be >= 1");
  if (!(settings.rel_tolerance > 0.0)) throw InputError("quasi_static: rel_tolerance must be > 0");
  if (!(settings.frame_s > 0.0)) throw InputError("quasi_static: frame_s must be > 0");
  const auto& disc = problem.discretization();
  if (problem.num_constrained() == 0)
    throw InputError("key 'regions': quasi_static needs a fixed or displacement region; a static solution needs supports");
  const Index n = disc.num_nodes();
  free_slot_.assign(n, -1);
  for (Index i = 0; i < n; ++i)
    if (!problem.constrained()[i]) {
      free_slot_[i] = static_cast<Eigen::Index>(free_.size());
      free_.push_back(i);
    }
  contact_of_.assign(n, -1);
  contact_lambda_.assign(n, 0.0);
  contact_normal_.assign(n, Vec3::Zero());
  const std::size_t tools = problem.tools().size();
  geometry_.resize(tools);
  posed_.assign(tools, 0);
  posed_geometry_.resize(tools);
  posed_point_.assign(tools, Vec3::Zero());
  place_tools(0.0);
  obstacle_load_.assign(tools, ObstacleLoad{});
  build_preconditioner();
}

void QuasiStaticModel::build_preconditioner() {
  // The tets' linear stiffness restricted to the free dofs.
  const auto& disc = problem_.discretization();
  const auto& E = problem_.energy();
  const Eigen::SparseMatrix<double> K = linear_tet_stiffness(disc.rest_positions(), disc.tets(),
                                                             E.strain_lambda() + E.options().volume_stiffness_pa,
                                                             E.shear_modulus());
  std::vector<Eigen::Triplet<double>> trip;
  for (int c = 0; c < K.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(K, c); it; ++it) {
      const Eigen::Index a = free_slot_[it.row() / 3], b = free_slot_[it.col() / 3];
      if (a >= 0 && b >= 0) trip.emplace_back(3 * a + it.row() % 3, 3 * b + it.col() % 3, it.value());
    }
  const Eigen::Index nf = static_cast<Eigen::Index>(free_.size()) * 3;
  Eigen::SparseMatrix<double> Kff(nf, nf);
  Kff.setFromTriplets(trip.begin(), trip.end());
  if (settings_.preconditioner == "auto")
    settings_.preconditioner = free_.size() <= 10000 ? "cholesky" : "incomplete_cholesky";
  if (settings_.preconditioner != "incomplete_cholesky" && settings_.preconditioner != "cholesky" &&
      settings_.preconditioner != "none")
    throw InputError("quasi_static: preconditioner must be auto, incomplete_cholesky, cholesky or none");
  if (nf > 0 && settings_.preconditioner == "cholesky") {
    cholesky_.compute(Kff);
    have_precond_ = cholesky_.info() == Eigen::Success && (cholesky_.vectorD().array() > 0.0).all();
  } else if (nf > 0 && settings_.preconditioner == "incomplete_cholesky") {
    incomplete_.compute(Kff);
    have_precond_ = incomplete_.info() == Eigen::Success;
  }
  if (nf > 0 && settings_.preconditioner != "none") {
    if (!have_precond_)
      spdlog::warn("quasi_static: the tetrahedral preconditioner is singular (is every part of the body "
                   "supported?); using no preconditioner");
  }
}

void QuasiStaticModel::place_tools(double s) {
  const auto& tools = problem_.tools();
  for (std::size_t o = 0; o < geometry_.size(); ++o) geometry_[o] = posed_[o] ? posed_geometry_[o] : obstacle_at(tools[o], s);
}

Vec3 QuasiStaticModel::tool_point(std::size_t o, double s) const {
  return posed_[o] ? posed_point_[o] : tool_point_at(problem_.tools()[o], s);
}

void QuasiStaticModel::set_tool_pose(std::size_t tool, const Vec3& position_m, const Eigen::Quaterniond& orientation) {
  posed_geometry_.at(tool) = obstacle_posed(problem_.tools().at(tool), position_m, orientation);
  posed_point_[tool] = position_m;
  posed_[tool] = 1;
}

StepReport QuasiStaticModel::step() {
  StepReport r = solve(1.0);
  t_ += settings_.frame_s;
  r.time_s = t_;
  return r;
}

void QuasiStaticModel::filter(Vec3Array& v) const {
  if (geometry_.empty()) return;
  for (Index i : free_)
    if (contact_of_[i] >= 0) v[i] -= contact_normal_[i].dot(v[i]) * contact_normal_[i];
}

int QuasiStaticModel::project_contacts(Vec3Array& x, bool add) {
  int added = 0;
  const int no = static_cast<int>(geometry_.size());
  if (no == 0) return 0;
  for (Index i : free_) {
    int& o = contact_of_[i];
    if (o < 0) {
      if (!add) continue;
      // The deepest penetration, if any.
      double deepest = 0.0;
      for (int k = 0; k < no; ++k) {
        const double c = obstacle_contact(geometry_[k], x[i]).value;
        if (c < deepest) deepest = c, o = k;
      }
      if (o < 0) continue;
      ++added;
    }
    // Onto the surface along the normal (a contact in the active set is held on the surface).
    const auto c = obstacle_contact(geometry_[o], x[i]);
    x[i] -= c.value * c.normal;
    contact_normal_[i] = c.normal;
  }
  return added;
}

void QuasiStaticModel::add_contact_curvature(const Vec3Array& x, const Vec3Array& p, Vec3Array& Hp) const {
  // A node held on a curved tool surface by the normal force lambda feels, when it slides by t along the
  // surface, the turn of that force: the Lagrangian's Hessian gains -lambda grad^2 phi, with
  // grad^2 phi = (I - n n^T - e e^T) / d (d the distance to the tool's core, e the capsule axis on the
  // cylindrical part, e = 0 on the rounded ends). Without it Newton converges only linearly.
  for (Index i : free_) {
    const int o = contact_of_[i];
    if (o < 0) continue;  // both signs: while in the set the contact is bilateral
    const constraints::Capsule& g = geometry_[static_cast<std::size_t>(o)];
    const Vec3 n = contact_normal_[i];
    Vec3 t = p[i] - n.dot(p[i]) * n;
    const Vec3 ab = g.b - g.a;
    const double len2 = ab.squaredNorm();
    if (len2 > 0.0) {
      const double u = (x[i] - g.a).dot(ab) / len2;
      if (u > 0.0 && u < 1.0) {
        const Vec3 e = ab / std::sqrt(len2);
        t -= e.dot(t) * e;
      }
    }
    Hp[i] -= (contact_lambda_[i] / g.radius_m) * t;
  }
}

int QuasiStaticModel::release_pulling_contacts(const Vec3Array& r) {
  int released = 0;
  for (Index i : free_)
    if (contact_of_[i] >= 0 && -r[i].dot(contact_normal_[i]) < 0.0) {
      contact_of_[i] = -1;
      ++released;
    }
  return released;
}

void QuasiStaticModel::measure_contacts(const Vec3Array& r, double s) {
  for (std::size_t o = 0; o < obstacle_load_.size(); ++o) obstacle_load_[o] = ObstacleLoad{};
  for (Index i : free_) {
    const int o = contact_of_[i];
    if (o < 0) continue;
    // Equilibrium in the normal direction: r_i + lambda n_i = 0.
    const Vec3 f = (-r[i].dot(contact_normal_[i])) * contact_normal_[i];
    ObstacleLoad& load = obstacle_load_[static_cast<std::size_t>(o)];
    load.force_n += f;
    load.torque_n_m += (x_[i] - tool_point(static_cast<std::size_t>(o), s)).cross(f);
    ++load.contacts;
  }
}

void QuasiStaticModel::precondition(const Vec3Array& r, Vec3Array& z) const {
  z.assign(r.size(), Vec3::Zero());
  if (!have_precond_) {
    for (Index i : free_) z[i] = r[i];
    filter(z);
    return;
  }
  Eigen::VectorXd b(static_cast<Eigen::Index>(free_.size()) * 3);
  for (std::size_t a = 0; a < free_.size(); ++a) b.segment<3>(3 * static_cast<Eigen::Index>(a)) = r[free_[a]];
  const Eigen::VectorXd y = settings_.preconditioner == "cholesky" ? Eigen::VectorXd(cholesky_.solve(b))
                                                                    : Eigen::VectorXd(incomplete_.solve(b));
  for (std::size_t a = 0; a < free_.size(); ++a) z[free_[a]] = y.segment<3>(3 * static_cast<Eigen::Index>(a));
  filter(z);
}

double QuasiStaticModel::residual_norm(const Vec3Array& r) const {
  double s = 0.0;
  for (Index i : free_) s += r[i].squaredNorm();
  return std::sqrt(s);
}

double QuasiStaticModel::potential(const Vec3Array& x, const Vec3Array& f_ext) const {
  // The work term uses displacements, not positions: f . X is a constant that would swamp the
  // differences the line search compares.
  const Vec3Array& X = problem_.discretization().rest_positions();
  double work = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) work += f_ext[i].dot(x[i] - X[i]);
  return problem_.energy().energy(x).total() - work;
}

int QuasiStaticModel::conjugate_gradients(const Vec3Array& x, const Vec3Array& rhs, double eta,
                                          Vec3Array& dx) const {
  const std::size_t n = x.size();
  dx.assign(n, Vec3::Zero());
  Vec3Array r(n, Vec3::Zero()), z, p, Hp;
  const auto lin = problem_.energy().linearize(x);
  for (Index i : free_) r[i] = rhs[i];
  filter(r);
  const double target = eta * residual_norm(r);
  precondition(r, z);
  p = z;
  double rz = dot(r, z);
  int it = 0;
  for (; it < settings_.max_cg_iterations; ++it) {
    problem_.energy().hessian_product(lin, p, Hp);
    for (std::size_t i = 0; i < n; ++i)
      if (problem_.constrained()[i]) Hp[i].setZero();
    add_contact_curvature(x, p, Hp);
    filter(Hp);
    const double pHp = dot(p, Hp);
    if (!(pHp > 0.0)) {
      // Negative curvature (SVK under compression): keep what we have, or the preconditioned gradient.
      if (it == 0) dx = z;
      break;
    }
    const double alpha = rz / pHp;
    for (std::size_t i = 0; i < n; ++i) {
      dx[i] += alpha * p[i];
      r[i] -= alpha * Hp[i];
    }
    if (residual_norm(r) <= target) {
      ++it;
      break;
    }
    precondition(r, z);
    const double rz_next = dot(r, z);
    const double beta = rz_next / rz;
    rz = rz_next;
    for (std::size_t i = 0; i < n; ++i) p[i] = z[i] + beta * p[i];
  }
  return it;
}

void QuasiStaticModel::predict(double s, const Vec3Array& f_ext, StepReport& rep) {
  // From the second load step on: secant extrapolation along the load path (nearly exact for a smooth path,
  // and free). Otherwise the linear one: move the constrained nodes by their increment and the free nodes by
  // the linear response to it, H_ff dx_f = r_f - H_fc dp_c (this avoids crushing the layer next to a driven
  // region).
  const auto& E = problem_.energy();
  const Index n = problem_.discretization().num_nodes();
  Vec3Array dp(n, Vec3::Zero());
  bool moved = false;
  for (Index i = 0; i < n; ++i)
    if (problem_.constrained()[i]) {
      dp[i] = problem_.prescribed_position(i, s) - x_[i];
      moved = moved || dp[i].squaredNorm() > 0.0;
    }
  Vec3Array base = x_;
  for (Index i = 0; i < n; ++i)
    if (problem_.constrained()[i]) base[i] += dp[i];
  // Tools: move them to s; nodes in contact (and nodes the tools now enter) go onto their surfaces, a
  // prescribed normal increment like the one above.
  place_tools(s);
  if (!geometry_.empty()) {
    project_contacts(base, true);
    for (Index i : free_)
      if (contact_of_[i] >= 0) {
        dp[i] = base[i] - x_[i];
        moved = moved || dp[i].squaredNorm() > 0.0;
      }
  }
  Vec3Array trial = base;
  if (!x_prev_.empty() && s_ != s_prev_) {
    const double q = (s - s_) / (s_ - s_prev_);
    for (Index i = 0; i < n; ++i)
      if (!problem_.constrained()[i] && contact_of_[i] < 0) trial[i] = x_[i] + q * (x_[i] - x_prev_[i]);
    project_contacts(trial, true);
  } else {
    Vec3Array f_int, r(n), dx, Hd;
    E.forces(x_, f_int);
    for (Index i = 0; i < n; ++i) r[i] = f_int[i] + f_ext[i];
    if (moved) {
      E.hessian_product(x_, dp, Hd);
      for (Index i = 0; i < n; ++i) r[i] -= Hd[i];
    }
    rep.inner_iterations += conjugate_gradients(x_, r, 1e-2, dx);
    for (Index i = 0; i < n; ++i)
      if (!problem_.constrained()[i]) trial[i] += dx[i];
    project_contacts(trial, true);
  }
  x_prev_ = x_;
  s_prev_ = s_;
  x_ = potential(trial, f_ext) <= potential(base, f_ext) ? trial : base;
}

double QuasiStaticModel::residual(double s, const Vec3Array& f_ext, Vec3Array& r, Vec3Array& r_unfiltered) {
  // r = f_int + f_ext; scaled by the larger of the reactions (supports and tools) and the applied loads.
  const Index n = problem_.discretization().num_nodes();
  Vec3Array f_int;
  problem_.energy().forces(x_, f_int);
  double reaction2 = 0.0, ext2 = 0.0;
  for (Index i = 0; i < n; ++i) {
    r[i] = f_int[i] + f_ext[i];
    ext2 += f_ext[i].squaredNorm();
    if (problem_.constrained()[i]) reaction2 += r[i].squaredNorm();
    if (contact_of_[i] >= 0) reaction2 += std::pow(r[i].dot(contact_normal_[i]), 2);
  }
  const double scale = std::max(std::sqrt(std::max(reaction2, ext2)), 1e-300);
  if (!geometry_.empty()) {
    r_unfiltered = r;
    for (Index i : free_) contact_lambda_[i] = contact_of_[i] >= 0 ? -r[i].dot(contact_normal_[i]) : 0.0;
    filter(r);
  }
  const double res = residual_norm(r) / scale;
  if (!std::isfinite(res)) throw NumericalError(fmt::format("quasi_static: non-finite residual at s = {:.4g}", s));
  return res;
}

bool QuasiStaticModel::line_search(const Vec3Array& r, const Vec3Array& f_ext, Vec3Array& dx, Vec3Array& trial) {
  // Backtracking Armijo line search on Pi: the directional derivative is -r . dx.
  const Index n = problem_.discretization().num_nodes();
  const double slope = -dot(r, dx);
  if (!(slope < 0.0)) {
    for (Index i : free_) dx[i] = r[i];  // not a descent direction: fall back to the gradient
  }
  const double pi0 = potential(x_, f_ext);
  const double g = std::min(-dot(r, dx), 0.0);
  double step = 1.0;
  for (int ls = 0; ls < 40; ++ls, step *= 0.5) {
    for (Index i = 0; i < n; ++i) trial[i] = x_[i] + step * dx[i];
    project_contacts(trial, false);
    const double pi = potential(trial, f_ext);
    if (std::isfinite(pi) && pi <= pi0 + 1e-4 * step * g) return true;
    if (ls == 0) {
      // Near the solution the energy decrease falls below round-off; accept the full step when
      // it reduces the force residual instead.
      Vec3Array f_trial;
      problem_.energy().forces(trial, f_trial);
      for (Index i : free_) f_trial[i] += f_ext[i];
      filter(f_trial);
      double r2 = 0.0;
      for (Index i : free_) r2 += f_trial[i].squaredNorm();
      if (std::isfinite(r2) && std::sqrt(r2) < 0.9 * residual_norm(r)) return true;
    }
  }
  return false;
}

StepReport QuasiStaticModel::solve(double s) {
  const Index n = problem_.discretization().num_nodes();
  StepReport rep;
  rep.load_factor = s;
  Vec3Array f_ext, r(n), r_unfiltered, dx, trial(n);
  problem_.external_forces(s, f_ext);
  predict(s, f_ext, rep);

  // Newton iterations.
  double res = 0.0, best = INFINITY;
  int stalled = 0, passes = 0;
  for (int it = 0;; ++it) {
    res = residual(s, f_ext, r, r_unfiltered);
    if (spdlog::should_log(spdlog::level::debug)) {
      int active = 0, pulling = 0;
      for (Index i : free_)
        if (contact_of_[i] >= 0) {
          ++active;
          pulling += contact_lambda_[i] < 0.0 ? 1 : 0;
        }
      spdlog::debug("quasi_static: s = {:.4g}, Newton {}: relative residual {:.3e}{}", s, it, res,
                    geometry_.empty() ? std::string() : fmt::format(" ({} contacts, {} pulling)", active, pulling));
    }
    // Nearly converged for this active set (1e-3, well before the tolerance, so that Newton does not polish
    // a set that is about to change): release the contacts that pull on a tool and iterate again; done when
    // converged and nothing pulls.
    if (!geometry_.empty() && res <= std::max(settings_.rel_tolerance, 1e-3)) {
      const int released = release_pulling_contacts(r_unfiltered);
      if (released > 0) {
        ++contact_passes_;
        spdlog::debug("quasi_static: s = {:.4g}: released {} contacts that pulled", s, released);
        if (++passes > settings_.max_contact_passes) {
          rep.converged = false;
          measure_contacts(r_unfiltered, s);
          break;
        }
        stalled = 0;
        best = INFINITY;
        continue;
      }
    }
    if (res <= settings_.rel_tolerance) {
      if (!geometry_.empty()) measure_contacts(r_unfiltered, s);
      break;
    }
    // Positions carry about 1e-16 relative precision, which floors the attainable residual; stop
    // when three Newton steps in a row gain less than 10 %.
    stalled = res < 0.9 * best ? 0 : stalled + 1;
    best = std::min(best, res);
    if (it == settings_.max_newton_iterations || stalled >= 3) {
      rep.converged = false;
      if (!geometry_.empty()) measure_contacts(r_unfiltered, s);
      break;
    }
    ++rep.iterations;
    // Forcing term: Eisenstat-Walker-style sqrt(res), but no tighter than the step needs to reach the
    // tolerance (the last Newton step would otherwise overshoot it by orders of magnitude).
    const double eta = std::clamp(std::max(std::sqrt(res), 0.3 * settings_.rel_tolerance / res), 1e-6, 0.1);
    const int cg = conjugate_gradients(x_, r, eta, dx);
    rep.inner_iterations += cg;
    spdlog::debug("quasi_static:   CG {} iterations (eta {:.1e})", cg, eta);
    if (!line_search(r, f_ext, dx, trial)) {
      rep.converged = false;
      break;
    }
    x_.swap(trial);
    // Nodes the step pushed into a tool join the active set on its surface.
    if (const int added = project_contacts(x_, true); added > 0) {
      spdlog::debug("quasi_static:   {} nodes entered a tool", added);
      stalled = 0;
      best = INFINITY;
    }
  }
  finish_step(s, res, rep);
  return rep;
}

void QuasiStaticModel::finish_step(double s, double res, StepReport& rep) {
  rep.residual = res;
  s_ = s;
  total_newton_ += rep.iterations;
  total_cg_ += rep.inner_iterations;
  if (rep.converged) return;
  ++unconverged_steps_;
  const std::string msg = fmt::format(
      "quasi_static: load factor {:.4g} did not converge (relative residual {:.3g} > {:.1g} after {} Newton "
      "iterations)",
      s, res, settings_.rel_tolerance, rep.iterations);
  if (settings_.fail_on_divergence) throw NumericalError(msg);
  spdlog::warn("{}", msg);
}

StepReport QuasiStaticModel::advance(int k) {
  return solve(static_cast<double>(k) / settings_.load_steps);
}

nlohmann::json QuasiStaticModel::info() const {
  return {{"model", "quasi_static"},
          {"load_steps", settings_.load_steps},
          {"rel_tolerance", settings_.rel_tolerance},
          {"preconditioner", have_precond_ ? settings_.preconditioner + " of the tet linear stiffness" : "none"},
          {"newton_iterations", total_newton_},
          {"cg_iterations", total_cg_},
          {"unconverged_steps", unconverged_steps_},
          {"contact_passes", contact_passes_},
          {"frame_s", settings_.frame_s}};
}

}  // namespace vascsim
