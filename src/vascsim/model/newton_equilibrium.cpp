#include "vascsim/model/newton_equilibrium.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <algorithm>
#include <cmath>

#include "vascsim/core/error.hpp"

namespace vascsim {

namespace {
double dot(const Vec3Array& a, const Vec3Array& b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += a[i].dot(b[i]);
  return s;
}
}  // namespace

NewtonEquilibrium::NewtonEquilibrium(const Problem& problem, const FreeDofs& free, ContactActiveSet& contacts,
                                     const NewtonSettings& settings)
    : problem_(problem),
      free_(free),
      contacts_(contacts),
      settings_(settings),
      compliance_(free),
      correction_(free, contacts) {
  const Discretization& disc = problem.discretization();
  force_floor_ = 1e-8 * disc.material().youngs_modulus_pa * disc.mean_spacing() * disc.mean_spacing();
  // The rest state's own forces are rounding (each fit carries its conditioning into F - I, a quadratic fit's
  // up to 1e4 times the unit roundoff): an unloaded step must be converged there, not iterate on that noise,
  // so the floor is at least 10 / rel_tolerance times it (about 1e-7 N on the vein at 0.3 mm, where the loads
  // are mN).
  Vec3Array f_rest;
  problem.energy().forces(disc.rest_positions(), f_rest, false);
  double noise2 = 0.0;
  for (Index i : free.nodes) noise2 += f_rest[static_cast<std::size_t>(i)].squaredNorm();
  force_floor_ = std::max(force_floor_, 10.0 * std::sqrt(noise2) / settings.rel_tolerance);
}

double NewtonEquilibrium::residual_norm(const Vec3Array& r) const {
  double s = 0.0;
  for (Index i : free_.nodes) s += r[i].squaredNorm();
  return std::sqrt(s);
}

double NewtonEquilibrium::potential(const Vec3Array& x, const Vec3Array& f_ext,
                                    const InertiaTerm& inertia) const {
  const Vec3Array& X = problem_.discretization().rest_positions();
  double work = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) work += f_ext[i].dot(x[i] - X[i]);
  double kinetic = 0.0;
  if (inertia.active()) {
    const auto& m = problem_.discretization().masses();
    const Vec3Array& a = *inertia.anchor;
    for (Index i : free_.nodes) kinetic += m[i] * (x[i] - a[i]).squaredNorm();
    kinetic *= 0.5 * inertia.inv_h2;
  }
  const double contact = embedded_ ? embedded_->energy(x) : 0.0;
  return problem_.energy().energy(x).total() + contact - work + kinetic;
}

void NewtonEquilibrium::precondition(const Vec3Array& r, Vec3Array& z) const {
  if (preconditioner_ == nullptr || !preconditioner_->apply(r, z)) {
    z.assign(r.size(), Vec3::Zero());
    for (Index i : free_.nodes) z[i] = r[i];
  } else if (use_correction_) {
    correction_.apply(z);
  }
  contacts_.filter(z);
}

void NewtonEquilibrium::hessian_product(const PointPrimitiveEnergy::Linearization& lin, const Vec3Array& x,
                                        const Vec3Array& p, const InertiaTerm& inertia, Vec3Array& Hp,
                                        bool smoothing) const {
  if (single_)
    single_->product(p, Hp, smoothing ? ProductForm::Smoothing : ProductForm::Exact);
  else
    problem_.energy().hessian_product(lin, p, Hp);
  if (embedded_) embedded_->add_hessian_product(p, Hp, smoothing || settings_.contact_normal_stiffness_only);
  for (std::size_t i = 0; i < Hp.size(); ++i)
    if (problem_.constrained()[i]) Hp[i].setZero();
  if (inertia.active()) {
    const auto& m = problem_.discretization().masses();
    for (Index i : free_.nodes) Hp[i] += (inertia.inv_h2 * m[i]) * p[i];
  }
  if (!smoothing) contacts_.add_curvature(x, p, Hp);
  contacts_.filter(Hp);
}

int NewtonEquilibrium::conjugate_gradients(const Vec3Array& x, const Vec3Array& rhs, double eta,
                                           const InertiaTerm& inertia, Vec3Array& dx,
                                           SteadyClock::time_point deadline, double* reduction) const {
  const std::size_t n = x.size();
  dx.assign(n, Vec3::Zero());
  Vec3Array r(n, Vec3::Zero()), z, p, Hp;
  const auto lin = single_ ? PointPrimitiveEnergy::Linearization{} : problem_.energy().linearize(x);
  if (single_) single_->linearize(x);
  // (solve() says when the residual it just evaluated at x left the embedded contact linearised there.)
  if (embedded_ && !carried_ && !embedded_linearized_) embedded_->linearize(x);
  embedded_linearized_ = false;
  use_correction_ = preconditioner_ != nullptr && !preconditioner_->handles_contacts() &&
                    !contacts_.empty() && correction_.update(*preconditioner_, compliance_);
  // A multigrid preconditioner smooths with this very matrix (the linearisation above).
  const NewtonOperator op = [&](const Vec3Array& v, Vec3Array& out) {
    hessian_product(lin, x, v, inertia, out, single_ != nullptr);
  };
  struct OperatorScope {
    const EquilibriumPreconditioner* p;
    ~OperatorScope() {
      if (p) p->set_operator(nullptr);
    }
  } scope{preconditioner_};
  if (preconditioner_) preconditioner_->set_operator(&op);
  for (Index i : free_.nodes) r[i] = rhs[i];
  contacts_.filter(r);
  const double r0 = residual_norm(r);
  const double target = eta * r0;
  if (reduction) *reduction = 1.0;
  precondition(r, z);
  p = z;
  double rz = dot(r, z);
  int it = 0;
  for (; it < settings_.max_cg_iterations; ++it) {
    hessian_product(lin, x, p, inertia, Hp);
    const double pHp = dot(p, Hp);
    if (!(pHp > 0.0)) {
      // Negative curvature (SVK under compression): keep what we have, or the preconditioned gradient.
      spdlog::debug("equilibrium:   CG met curvature {:.3e} at iteration {} (|p|^2 {:.3e}, r.z {:.3e})", pHp,
                    it, dot(p, p), rz);
      if (it == 0) dx = z;
      break;
    }
    const double alpha = rz / pHp;
    for (std::size_t i = 0; i < n; ++i) {
      dx[i] += alpha * p[i];
      r[i] -= alpha * Hp[i];
    }
    const double rk = residual_norm(r);
    if (reduction && r0 > 0.0) *reduction = rk / r0;
    if (rk <= target || SteadyClock::now() >= deadline) {
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

double NewtonEquilibrium::residual(Vec3Array& x, double s, const Vec3Array& f_ext, const InertiaTerm& inertia,
                                   Vec3Array& r) {
  // r = f_int + f_ext - inertial force; scaled by the largest of the reactions (supports and tools), the
  // applied loads and the inertial forces.
  const Index n = problem_.discretization().num_nodes();
  Vec3Array f_int;
  if (settings_.reuse_forces && same_state(x, forces_x_)) {
    f_int = forces_;
    ++force_evaluations_reused_;
  } else {
    if (float_forces()) {
      single_->linearize(x);
      single_->forces(f_int);
    } else {
      problem_.energy().forces(x, f_int, false);
    }
    ++force_evaluations_;
    if (settings_.reuse_forces) {
      forces_x_ = x;
      forces_ = f_int;
    }
  }
  double reaction2 = 0.0, ext2 = 0.0, inertial2 = 0.0;
  if (embedded_) {
    if (carried_)
      embedded_->relinearize_carried(x);
    else
      embedded_->linearize(x);
    embedded_->add_forces(f_int);
    reaction2 = embedded_->squared_force();
  }
  const auto& m = problem_.discretization().masses();
  for (Index i = 0; i < n; ++i) {
    r[i] = f_int[i] + f_ext[i];
    ext2 += f_ext[i].squaredNorm();
    if (problem_.constrained()[i]) {
      reaction2 += r[i].squaredNorm();
    } else if (inertia.active()) {
      const Vec3 f_inertia = (inertia.inv_h2 * m[i]) * (x[i] - (*inertia.anchor)[i]);
      r[i] -= f_inertia;
      inertial2 += f_inertia.squaredNorm();
    }
    if (contacts_.in_contact(i)) reaction2 += std::pow(r[i].dot(contacts_.normal(i)), 2);
  }
  const double scale =
      std::max(std::sqrt(std::max({reaction2, ext2, inertial2})), std::max(force_floor_, 1e-300));
  r_unfiltered_ = r;
  if (!contacts_.empty()) {
    contacts_.update_lambdas(r);
    contacts_.filter(r);
  }
  const double res = residual_norm(r) / scale;
  if (!std::isfinite(res)) throw NumericalError(fmt::format("non-finite residual at load factor {:.4g}", s));
  return res;
}

bool NewtonEquilibrium::line_search(const Vec3Array& x, const Vec3Array& r, const Vec3Array& f_ext,
                                    const InertiaTerm& inertia, Vec3Array& dx, Vec3Array& trial) {
  // Backtracking Armijo line search on Pi: the directional derivative is -r . dx.
  const Index n = problem_.discretization().num_nodes();
  const double slope = -dot(r, dx);
  if (!(slope < 0.0)) {
    for (Index i : free_.nodes) dx[i] = r[i];  // not a descent direction: fall back to the gradient
  }
  // Pi(x) is known when x is the trial the previous line search accepted (and nothing moved it since).
  const double pi0 = accepted_potential_ ? *accepted_potential_ : potential(x, f_ext, inertia);
  accepted_potential_.reset();
  const double g = std::min(-dot(r, dx), 0.0);
  double step = 1.0;
  for (int ls = 0; ls < 40; ++ls, step *= 0.5) {
    for (Index i = 0; i < n; ++i) trial[i] = x[i] + step * dx[i];
    contacts_.project(trial, false);
    const double pi = potential(trial, f_ext, inertia);
    if (std::isfinite(pi) && pi <= pi0 + 1e-4 * step * g) {
      accepted_potential_ = pi;
      if (step < 1.0) spdlog::debug("equilibrium:   line search step {:.3g}", step);
      return true;
    }
    if (ls == 0) {
      // Near the solution the energy decrease falls below round-off; accept the full step when it reduces
      // the force residual instead.
      Vec3Array f_trial;
      problem_.energy().forces(trial, f_trial, false);
      if (embedded_) {
        embedded_->linearize(trial);
        embedded_->add_forces(f_trial);
      }
      const auto& m = problem_.discretization().masses();
      for (Index i : free_.nodes) {
        f_trial[i] += f_ext[i];
        if (inertia.active()) f_trial[i] -= (inertia.inv_h2 * m[i]) * (trial[i] - (*inertia.anchor)[i]);
      }
      contacts_.filter(f_trial);
      double r2 = 0.0;
      for (Index i : free_.nodes) r2 += f_trial[i].squaredNorm();
      if (std::isfinite(r2) && std::sqrt(r2) < 0.9 * residual_norm(r)) {
        accepted_potential_ = pi;
        return true;
      }
    }
  }
  return false;
}

NewtonResult NewtonEquilibrium::solve(Vec3Array& x, double s, const Vec3Array& f_ext,
                                      const InertiaTerm& inertia, SteadyClock::time_point deadline,
                                      bool carry_contacts, int max_iterations) {
  const int iteration_limit = max_iterations >= 0 ? max_iterations : settings_.max_newton_iterations;
  const Index n = problem_.discretization().num_nodes();
  struct CarryScope {
    bool& flag;
    ~CarryScope() { flag = false; }
  } carry_scope{carried_};
  carry_contacts = carry_contacts && embedded_ != nullptr && embedded_->active() > 0;
  const bool budgeted = deadline != SteadyClock::time_point::max();
  NewtonResult out;
  Vec3Array r(n), dx, trial(n);
  accepted_potential_.reset();  // x comes from outside
  double best = INFINITY;
  int stalled = 0;
  // deferred_line_search: the state before a step taken whole, its force residual and the step.
  const bool defer = settings_.line_search && settings_.deferred_line_search && contacts_.empty();
  Vec3Array x_before, dx_before, r_before;
  bool unchecked = false;
  bool moved = false;  // x changed since the preconditioner last followed it (the caller prepared the first)
  bool progress = false;  // a step of this solve was kept
  for (int it = 0;; ++it) {
    carried_ = carry_contacts && it == 0;
    out.residual = residual(x, s, f_ext, inertia, r);
    if (unchecked) {
      unchecked = false;
      if (!(residual_norm(r) < residual_norm(r_before))) {
        // The whole step made the forces worse: back to the state before it, and search along the step from
        // there (or, out of time, end there).
        spdlog::debug("equilibrium:   the whole step raised the residual to {:.3e}: line search",
                      out.residual);
        x.swap(x_before);
        accepted_potential_.reset();
        ++out.rejected_whole_steps;
        // Out of time, a solve ends there only if it kept a step before: otherwise it would end where it
        // began, and the next frame, from the same state with the same matrices, would take and reject the
        // very same step (a realtime frame of a hand held still, repeated until the coarse level changed).
        if (progress && it >= settings_.min_newton_iterations && SteadyClock::now() >= deadline) {
          out.residual = residual(x, s, f_ext, inertia, r);
        } else {
          if (!line_search(x, r_before, f_ext, inertia, dx_before, trial)) {
            spdlog::debug("equilibrium:   the line search found no decrease");
            out.residual = residual(x, s, f_ext, inertia, r);
            out.converged = false;
            break;
          }
          x.swap(trial);
          moved = true;
          progress = true;
          continue;
        }
      }
      progress = true;  // the whole step lowered the residual, or was searched above
    }
    if (spdlog::should_log(spdlog::level::debug))
      spdlog::debug("equilibrium: s = {:.4g}, Newton {}: relative residual {:.3e}{}", s, it, out.residual,
                    embedded_ ? fmt::format(" ({} samples in contact, tool force {:.4e} N)",
                                            embedded_->active(), std::sqrt(embedded_->squared_force()))
                    : contacts_.empty()
                        ? std::string()
                        : fmt::format(" ({} contacts, {} pulling)", contacts_.active(), contacts_.pulling()));
    // Nearly converged for this active set (1e-3, well before the tolerance, so that Newton does not polish
    // a set that is about to change): release the contacts that pull on a tool and iterate again; done when
    // converged and nothing pulls.
    // The carried step's residual is that of the moved tools against the unmoved wall: it says nothing of
    // convergence (a carried set whose tools hardly moved leaves the state converged: nothing to answer).
    const bool moving = it == 0 && carry_contacts && out.residual > settings_.rel_tolerance;
    if (!moving && !contacts_.empty() &&
        out.residual <= std::max(settings_.rel_tolerance, settings_.release_below_residual)) {
      const int released = contacts_.release_pulling(r_unfiltered_);
      if (released > 0) {
        spdlog::debug("equilibrium: s = {:.4g}: released {} contacts that pulled", s, released);
        if (++out.contact_passes > settings_.max_contact_passes) {
          out.converged = false;
          out.loads_measured = true;
          break;
        }
        stalled = 0;
        best = INFINITY;
        continue;
      }
    }
    if (!moving && out.residual <= settings_.rel_tolerance) {
      out.loads_measured = true;
      break;
    }
    // The position-precision floor (NewtonSettings::stall_below_residual): three Newton steps in a row that
    // gain less than 10 % there end the solve.
    stalled = out.residual < 0.9 * best || out.residual > settings_.stall_below_residual ? 0 : stalled + 1;
    best = std::min(best, out.residual);
    // The deadline counts from the settings' minimum of Newton steps on (the steps that make a frame's
    // force).
    const bool timed = it >= settings_.min_newton_iterations;
    const bool out_of_time = timed && SteadyClock::now() >= deadline;
    // (The carried step is taken whatever the time: a frame ends with the wall answering its tools' pose.)
    if (!moving && (it >= iteration_limit || stalled >= 3 || out_of_time)) {
      spdlog::debug("equilibrium:   stopped ({})", out_of_time    ? "out of time"
                                                   : stalled >= 3 ? "stalled"
                                                                  : "iteration limit");
      out.converged = false;
      out.out_of_time = out_of_time;
      out.loads_measured = true;
      break;
    }
    ++out.iterations;
    // Forcing term: Eisenstat-Walker-style sqrt(res), but no tighter than the step needs to reach the
    // tolerance (the last Newton step would otherwise overshoot it by orders of magnitude).
    // In a frame with a wall-time budget the cap follows ten times the residual up to far_forcing: such a
    // frame ends at its budget, not at the tolerance, and far from the equilibrium another relinearisation of
    // the contact is worth more than linear accuracy the next step discards. A frame that will converge keeps
    // max_forcing, whose tighter steps save CG restarts (lockstep press and slide on the real-time vein: 162
    // Newton / 739 CG against 250 / 1,179 with the far cap).
    const double far = budgeted ? settings_.far_forcing : 0.0;
    const double cap = std::max(settings_.max_forcing, std::min(10.0 * out.residual, far));
    const double eta =
        moving ? settings_.carried_forcing
               : std::clamp(std::max(std::sqrt(out.residual), 0.3 * settings_.rel_tolerance / out.residual),
                            1e-6, cap);
    double reduction = 1.0;
    if (moved && preconditioner_ != nullptr && settings_.follow_state) preconditioner_->follow_state(x);
    moved = false;
    embedded_linearized_ = !carried_;  // residual() above, at this x
    const int cg = conjugate_gradients(x, r, eta, inertia, dx,
                                       timed ? deadline : SteadyClock::time_point::max(), &reduction);
    out.cg_iterations += cg;
    if (cg > 0 && reduction > 0.0) out.cg_rate = std::max(out.cg_rate, std::pow(reduction, 1.0 / cg));
    spdlog::debug("equilibrium:   CG {} iterations (eta {:.1e})", cg, eta);
    if (embedded_ && settings_.max_step_m > 0.0) {
      const double limit =
          moving ? std::max(settings_.max_step_m, 2.0 * embedded_->carried_gap()) : settings_.max_step_m;
      double longest = 0.0;
      for (Index i : free_.nodes) longest = std::max(longest, dx[i].norm());
      if (!(longest <= limit)) {
        for (Vec3& d : dx) d = std::isfinite(longest) ? Vec3(d * (limit / longest)) : Vec3::Zero();
        ++out.limited_steps;
        spdlog::debug("equilibrium:   a step of {:.3e} m limited to {:.3e} m", longest, limit);
      }
    }
    // The carried step is taken whole, never searched: its contact forces are not the gradient of Pi.
    if (defer && !moving) {
      x_before = x;
      dx_before = dx;
      r_before = r;
      unchecked = true;
      for (std::size_t i = 0; i < x.size(); ++i) x[i] += dx[i];
      accepted_potential_.reset();
    } else if (settings_.line_search && !moving) {
      if (!line_search(x, r, f_ext, inertia, dx, trial)) {
        spdlog::debug("equilibrium:   the line search found no decrease");
        out.converged = false;
        break;
      }
      x.swap(trial);
      progress = true;
    } else {
      for (std::size_t i = 0; i < x.size(); ++i) x[i] += dx[i];
      accepted_potential_.reset();
      progress = true;
    }
    moved = true;
    // Nodes the step pushed into a tool join the active set on its surface.
    if (const int added = contacts_.project(x, true); added > 0) {
      accepted_potential_.reset();  // projected nodes moved
      spdlog::debug("equilibrium:   {} nodes entered a tool", added);
      stalled = 0;
      best = INFINITY;
    }
  }
  return out;
}

}  // namespace vascsim
