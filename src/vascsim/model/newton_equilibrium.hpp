#pragma once
// The equilibrium solve shared by `quasi_static` and `implicit` (docs/model/13-quasi-static-solver.md and
// docs/model/24-implicit.md): minimise
//   Pi(x) = U(x) - f_ext . (x - X) [+ 1/(2 h^2) sum_i m_i |x_i - a_i|^2]      over the free nodes,
// the bracket being backward Euler's inertia around a = x_n + h v_n (the implicit model; absent for a static
// solve), with the tools' frictionless contact by an active set (contact_active_set.hpp).
//
// Truncated Newton: each Newton system (K(x) [+ M/h^2]) dx = r is solved by preconditioned conjugate
// gradients on analytic Hessian-vector products (equilibrium_preconditioner.hpp: a factor of a matrix close
// to the Newton matrix); negative curvature stops CG early; a backtracking Armijo line search on Pi
// globalises; near convergence contacts that pull are released. Converged when |r_free| <= tol *
// max(|reactions|, |f_ext|, |inertial forces|). A deadline stops the iterations early (the real-time budget);
// the residual reached is reported either way.

#include <limits>
#include <optional>

#include "vascsim/core/stopwatch.hpp"
#include "vascsim/model/contact_active_set.hpp"
#include "vascsim/model/contact_correction.hpp"
#include "vascsim/model/embedded_contact.hpp"
#include "vascsim/model/equilibrium_preconditioner.hpp"
#include "vascsim/model/single_precision_hessian.hpp"

namespace vascsim {

struct NewtonSettings {
  double rel_tolerance = 1e-8;     ///< relative force residual at convergence
  int max_newton_iterations = 60;  ///< per solve
  int max_cg_iterations = 2000;    ///< per Newton iteration
  int max_contact_passes = 50;     ///< active-set changes after a converged Newton solve, per solve
  /// Backtracking Armijo line search on Pi (robust for large load increments). Without it every Newton step
  /// is taken whole, which saves an energy evaluation per iteration when the increments are small (real-time
  /// frames warm-started from the last equilibrium).
  bool line_search = true;
  /// With line_search and the tools on the wall's surface (or none): each Newton step is first taken whole,
  /// and the line search runs only when the force residual there is no smaller than before the step (then
  /// from the state before it). The energy evaluations of an accepted step (two at a solve's first step) are
  /// saved; a solve that ends right after a rejected step ends at the state before it.
  bool deferred_line_search = false;
  /// Contacts that pull are released once the relative residual is below this (1e-3: well before the
  /// tolerance, so that Newton does not polish an active set that is about to change). A real-time frame,
  /// which stops after a few iterations, releases at any residual (infinity).
  double release_below_residual = 1e-3;
  /// Positions carry about 1e-16 relative precision, which floors the attainable residual: below this
  /// relative residual, three Newton steps in a row that gain less than 10 % end the solve (not converged, at
  /// the floor). Above it a slow stretch is progress (a contact settling), not the floor.
  double stall_below_residual = 1e-5;
  /// Embedded contact's Newton matrix with only the penalty's normal stiffness
  /// (EmbeddedContact::add_hessian_product): for solves whose tools move a long way between linearisations.
  bool contact_normal_stiffness_only = false;
  /// Newton steps a solve takes before its deadline can stop it (the prescribed first step counts).
  int min_newton_iterations = 0;
  /// The largest forcing term: a Newton step's CG reduces its residual at least this much (Eisenstat-Walker
  /// sqrt(residual) below it, and no tighter than the step needs to reach the tolerance).
  double max_forcing = 0.1;
  /// In a solve with a deadline, far from the equilibrium the cap loosens with the residual: a step at
  /// relative residual r may stop its CG at a cap of min(10 r, far_forcing) where that exceeds max_forcing
  /// (0: the cap is max_forcing throughout; a solve without a deadline always uses max_forcing). Where a
  /// frame ends at its budget and its step's own linearisation (the contact set, above all) leaves it far
  /// off, CG iterations past that reduction are lost to the next step's relinearisation.
  double far_forcing = 0.0;
  /// The forcing term of a solve's carried first step (embedded contact, `carry_contacts`): its CG stops when
  /// it has reduced the step's residual this much. The carried contact set is itself a linearisation of the
  /// tools' move, which leaves the step a relative residual of 0.05-0.3 whatever CG does, so solving the
  /// step's system far below that buys nothing the next step keeps.
  double carried_forcing = 0.1;
  /// Tools on the wall's surface: the longest a Newton step may move a node, m (0: no limit); a longer step
  /// is scaled down to it, and a carried step to twice the tools' move if that is longer. Where compression
  /// makes the Newton matrix indefinite, CG's iterates can grow without bound before it meets the negative
  /// curvature, and a carried step (taken whole) or a whole step of the deferred line search would take the
  /// wall there (under the soak's random hand, a step of metres, then a non-finite state).
  double max_step_m = 0.0;
  /// A residual at the very state of the last one (bit for bit) reuses its internal forces: a real-time
  /// frame's carried steps each end with a residual at the state the next one starts from, and a frame ends
  /// at the state the next frame starts from unless it predicts a new one. Off only to check that reusing
  /// changes nothing.
  bool reuse_forces = true;
  /// Each Newton step after a solve's first lets the preconditioner re-form its state-bound part at the
  /// step's own state (EquilibriumPreconditioner::follow_state: the multigrid's window round the tools, when
  /// a step changed the contact samples in it). Off only to measure what it saves.
  bool follow_state = true;
  /// With single-precision products (set_single_precision): the residuals' internal forces in float too
  /// (SinglePrecisionHessian::forces, from the linearisation the step's conjugate gradients then use), about
  /// 1e-6 of the forces in play; for tolerances of 1e-4 and looser.
  bool single_precision_forces = false;
};

/// Backward Euler's inertia term: 1/(2 h^2) sum_i m_i |x_i - a_i|^2 over the free nodes.
struct InertiaTerm {
  double inv_h2 = 0.0;                ///< 1/h^2, 1/s^2
  const Vec3Array* anchor = nullptr;  ///< a = x_n + h v_n, m; null: a static solve
  bool active() const { return anchor != nullptr && inv_h2 > 0.0; }
};

struct NewtonResult {
  int iterations = 0;      ///< Newton iterations
  int cg_iterations = 0;   ///< conjugate-gradient iterations, all Newton iterations together
  int contact_passes = 0;  ///< active-set releases
  double residual = 0.0;   ///< relative residual reached
  bool converged = true;
  bool out_of_time = false;      ///< stopped at the deadline
  int rejected_whole_steps = 0;  ///< deferred_line_search: whole steps that raised the residual (searched)
  int limited_steps = 0;         ///< Newton steps scaled down to max_step_m
  bool loads_measured = false;   ///< the contact reactions of the final state are in last_residual()
  /// How well the preconditioner matched the Newton matrix: the geometric mean, over the CG iterations of the
  /// solve, of the residual reduction per iteration (|r_k| / |r_0|)^(1/k); 0 when CG never ran. About 0.1 or
  /// less with a factor of the current matrix, approaching 1 as the factor goes stale.
  double cg_rate = 0.0;
};

class NewtonEquilibrium {
 public:
  NewtonEquilibrium(const Problem& problem, const FreeDofs& free, ContactActiveSet& contacts,
                    const NewtonSettings& settings);
  const NewtonSettings& settings() const { return settings_; }
  /// Residuals below this force (N) count as zero load: an unloaded frame is converged, not "infinitely" far
  /// from equilibrium. Default: 1e-8 of E Delta^2 (the force that strains one neighbourhood by 100 % is E
  /// Delta^2), or 10 / rel_tolerance times the rounding of the rest state's forces if that is larger.
  void set_force_floor(double newton) { force_floor_ = newton; }
  void set_preconditioner(EquilibriumPreconditioner* preconditioner) { preconditioner_ = preconditioner; }
  /// Conjugate gradients (and a multigrid preconditioner's smoothing) on the Hessian product in single
  /// precision (single_precision_hessian.hpp) instead of the energy's double one; null: double. For solves
  /// that need a relative accuracy far above 1e-7 (the real-time model's frames).
  void set_single_precision(SinglePrecisionHessian* product) { single_ = product; }
  /// Contact on the wall's surface (embedded_contact.hpp), one more energy term; null: none (the tools, if
  /// any, meet the nodes through the active set).
  void set_embedded_contact(EmbeddedContact* contact) { embedded_ = contact; }
  /// The contact compliance W over the contacts of the last solve, with the nodes and normals it belongs to
  /// (empty when the preconditioner has no multi-column solves).
  const ContactCorrection& contact_correction() const { return correction_; }
  /// Rebuilds the contact correction for the current contacts and preconditioner now (it is otherwise rebuilt
  /// by the next CG solve). False when there is none.
  bool update_contact_correction() const {
    return preconditioner_ != nullptr && !contacts_.empty() &&
           correction_.update(*preconditioner_, compliance_);
  }
  /// The per-node compliance cache of the current factor, shared with the haptic candidates.
  NodeCompliance& node_compliance() const { return compliance_; }

  /// Newton iterations from x (changed in place) to the equilibrium at load factor s with external forces
  /// f_ext (N per node), stopping at the tolerance, the iteration limits or the deadline. `carry_contacts`
  /// (embedded contact, tools moved since x): the first Newton step keeps the samples in contact at the last
  /// linearisation (EmbeddedContact::relinearize_carried), so that the wall answers the move of those
  /// contacts by its linear response, instead of meeting every sample the moved tools swept through at once
  /// (most of which that response takes out of contact again: a Newton iteration that starts there stalls for
  /// several steps). That step is taken whole, whatever the deadline. `max_iterations` (>= 0) overrides the
  /// settings' Newton limit for this solve: 1 takes the carried step alone and evaluates the residual (and
  /// the contacts) where it ends, a continuation step of a frame whose tools moved far.
  NewtonResult solve(Vec3Array& x, double s, const Vec3Array& f_ext, const InertiaTerm& inertia,
                     SteadyClock::time_point deadline = SteadyClock::time_point::max(),
                     bool carry_contacts = false, int max_iterations = -1);

  /// PCG on the Newton matrix at x (filtered at the contacts): dx with H dx = rhs to |res| <= eta |rhs|.
  /// Returns the iterations. Stops at negative curvature or the deadline.
  int conjugate_gradients(const Vec3Array& x, const Vec3Array& rhs, double eta, const InertiaTerm& inertia,
                          Vec3Array& dx, SteadyClock::time_point deadline = SteadyClock::time_point::max(),
                          double* reduction = nullptr) const;
  /// Pi(x) (J), the work term on displacements (f . X would swamp the differences the line search compares).
  double potential(const Vec3Array& x, const Vec3Array& f_ext, const InertiaTerm& inertia) const;
  /// |r| over the free nodes.
  double residual_norm(const Vec3Array& r) const;
  /// The unfiltered residual f_int + f_ext - inertia of the last evaluation (the contacts' reactions are
  /// -r.n); on prescribed nodes it is the support reaction.
  const Vec3Array& last_residual() const { return r_unfiltered_; }
  /// Internal-force evaluations the residuals needed, and those NewtonSettings::reuse_forces saved.
  long long force_evaluations() const { return force_evaluations_; }
  long long force_evaluations_reused() const { return force_evaluations_reused_; }
  const FreeDofs& free() const { return free_; }
  /// Whether the residuals' internal forces are in float (single-precision products and
  /// NewtonSettings::single_precision_forces).
  bool float_forces() const { return single_ != nullptr && settings_.single_precision_forces; }

 private:
  double residual(Vec3Array& x, double s, const Vec3Array& f_ext, const InertiaTerm& inertia, Vec3Array& r);
  void precondition(const Vec3Array& r, Vec3Array& z) const;
  /// smoothing: the operator a multigrid preconditioner smooths with (single-precision products only,
  /// ProductForm::Smoothing): the geometric stiffness clamped to positive semi-definite, no stabiliser and no
  /// contact curvature, so that the V-cycle stays symmetric positive definite where compression makes the
  /// exact Hessian indefinite, at about half a product's cost.
  void hessian_product(const PointPrimitiveEnergy::Linearization& lin, const Vec3Array& x, const Vec3Array& p,
                       const InertiaTerm& inertia, Vec3Array& Hp, bool smoothing = false) const;
  bool line_search(const Vec3Array& x, const Vec3Array& r, const Vec3Array& f_ext, const InertiaTerm& inertia,
                   Vec3Array& dx, Vec3Array& trial);

  const Problem& problem_;
  const FreeDofs& free_;
  ContactActiveSet& contacts_;
  NewtonSettings settings_;
  EquilibriumPreconditioner* preconditioner_ = nullptr;
  EmbeddedContact* embedded_ = nullptr;
  SinglePrecisionHessian* single_ = nullptr;
  Vec3Array r_unfiltered_;
  double force_floor_ = 0.0;
  bool carried_ = false;  // this evaluation keeps the embedded contact's carried-over set
  mutable bool embedded_linearized_ =
      false;                              // solve(): the residual linearised the embedded contact at CG's x
  mutable NodeCompliance compliance_;     // P^{-1} E_i per node, per factor (node_compliance.hpp)
  mutable ContactCorrection correction_;  // cached per contact set and factor (contact_correction.hpp)
  mutable bool use_correction_ = false;
  std::optional<double> accepted_potential_;  // Pi of the trial the last line search accepted, J
  Vec3Array forces_x_, forces_;               // the last internal forces and the state they are of
  long long force_evaluations_ = 0, force_evaluations_reused_ = 0;
};

}  // namespace vascsim
