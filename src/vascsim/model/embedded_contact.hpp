#pragma once
// Frictionless contact between the tools and the wall's surface, not its nodes (docs/model/22-contact.md
// section 22.5): a penalty on the penetration of the surface's quadrature points (contact_surface.hpp),
//   U_c(x) = sum_v (k a_v / 2) max(0, -C(x_v))^2,   x_v = S_v + sum_i phi_vi (x_i - X_i),
// C the tool's signed distance, k the contact stiffness (Pa/m) and a_v the sample's area. The tool's force is
// the sum of the samples' pressures times their areas, and the nodes receive phi_vi times each sample's
// force, so the reaction is consistent with the map (virtual work). The surface is smooth between the nodes,
// so the force does not depend on where the nodes fall under the tool, as it does for contact at the nodes.
//
// Used by the equilibrium solve (newton_equilibrium.hpp) as one more energy term: value, forces at a
// linearisation point, and Hessian-vector products there.

#include <vector>

#include "vascsim/model/contact_surface.hpp"
#include "vascsim/model/rigid_obstacle.hpp"

namespace vascsim {

class EmbeddedContact {
 public:
  /// `surface` (with the rest node positions X it was built on) must outlive this; `tools` the number of
  /// tools.
  EmbeddedContact(const ContactSurface& surface, const Vec3Array& rest_nodes_m, std::size_t tools);

  void place(std::size_t o, const constraints::Capsule& geometry) { geometry_.at(o) = geometry; }
  const constraints::Capsule& geometry(std::size_t o) const { return geometry_.at(o); }

  /// U_c at x, J.
  double energy(const Vec3Array& x) const;
  /// Finds the penetrating samples at x; forces, Hessian products and loads then refer to x.
  void linearize(const Vec3Array& x);
  /// Re-linearises at x (the tools placed anew) the samples that were in contact at the last linearisation,
  /// and only those: the contact set carried into a frame whose tools moved, so that its first Newton step
  /// answers their move without the samples the moved tools sweep through, most of which the wall's response
  /// takes out of contact again. A carried sample the tools left by a gap of at most set_carried_gap's is
  /// held there for that step, its penalty pulling it back (a tool sliding along the wall leaves the samples
  /// behind it: released, they would let the wall spring back into the tool, and the step would meet every
  /// sample ahead at once); farther ones drop out.
  void relinearize_carried(const Vec3Array& x);
  /// The gap up to which relinearize_carried holds a sample the tools left, m (0, the default: none; the
  /// length the tools moved since the last linearisation holds the samples a slide left).
  void set_carried_gap(double gap_m) { carried_gap_m_ = gap_m; }
  double carried_gap() const { return carried_gap_m_; }
  /// Adds the contact forces on the nodes (-dU_c/dx at the linearisation), N.
  void add_forces(Vec3Array& f) const;
  /// Adds (d^2 U_c/dx^2) p at the linearisation; with `normal_only`, only its positive semi-definite normal
  /// part k a_v n n^T (for_each_stiffness): a tool that moved into the wall since the linearisation
  /// penetrates deep, and the full Hessian's softening along the surface (depth / distance to the core) then
  /// outweighs the wall.
  void add_hessian_product(const Vec3Array& p, Vec3Array& Hp, bool normal_only = false) const;
  /// Per tool at the linearisation: the force on the tissue, its moment about tool_points[o] and the number
  /// of samples in contact.
  std::vector<ObstacleLoad> loads(const std::vector<Vec3>& tool_points) const;
  /// Per tool: the wall's own answer to the contact at the linearisation, -(f_int + f_ext - inertial force)
  /// summed over the free nodes its samples move (with several tools, a node's share by the weight of each
  /// tool's samples on it), and its moment about tool_points[o]; `residual` is the unfiltered force residual
  /// at the same state, whose sum there is the difference from loads(). The same force as loads() at an
  /// equilibrium; away from one, a far better estimate of the equilibrium's: the penalty makes a sample
  /// that is a micrometre off its equilibrium carry milli-newtons (on the real-time vein under a 2 mm/s
  /// hand, frames at relative residuals of 0.1-0.5 had penalty forces a median 66 % off the continuum, and
  /// this 5.5 %), while the wall's stiffness is that of the material.
  std::vector<ObstacleLoad> reaction_loads(const std::vector<Vec3>& tool_points, const Vec3Array& x,
                                           const Vec3Array& residual,
                                           const std::vector<char>& constrained) const;
  /// Sum over tools of |force on the tissue|^2 at the linearisation, N^2 (the equilibrium residual's scale).
  double squared_force() const;
  int active() const { return static_cast<int>(active_.size()); }
  /// Calls f(sample, k a_v, n) for every penetrating sample at the linearisation: its penalty stiffness (N/m)
  /// and unit normal out of the tool. k a_v n n^T is the normal part of d^2 U_c / dx_v^2, positive
  /// semi-definite (the whole Hessian softens along the surface by depth / distance to the tool's core, which
  /// a preconditioner need not see). The sample's nodes and weights are row `sample` of surface().
  template <class F>
  void for_each_contact(F&& f) const {
    for (const Contact& c : active_) f(c.sample, c.normal.dot(c.stiffness * c.normal), c.normal);
  }
  const ContactSurface& surface() const { return surface_; }

 private:
  struct Contact {
    Index sample;
    int tool;
    Vec3 position;   // x_v, m
    Vec3 normal;     // out of the tool
    double depth;    // penetration, m (> 0)
    Vec3 force;      // k a_v depth n: the sample's force on the tissue, N
    Mat3 stiffness;  // d^2 U_c / dx_v^2, N/m
  };
  Contact make_contact(Index v, int o, const Vec3& xv, const constraints::ContactConstraint& c) const;
  // Calls f(v, o, x_v, C) for every sample that may penetrate a tool at x (bounded by the largest node
  // displacement) and does.
  template <class F>
  void for_each_penetration(const Vec3Array& x, F&& f) const;

  // The samples that may penetrate a tool while the tools stay within candidate_slack_m_ of where they were
  // when the list was made and no node moves farther than that from where it was then (ascending;
  // for_each_penetration).
  bool candidates_hold(const Vec3Array& x) const;
  Vec3 sample_position(Index v, const Vec3Array& x) const;  // x_v, m
  void make_candidates(const Vec3Array& x, double u_max) const;

  const ContactSurface& surface_;
  const Vec3Array& rest_nodes_;
  std::vector<constraints::Capsule> geometry_;
  mutable std::vector<Index> candidates_;
  mutable std::vector<constraints::Capsule> candidate_geometry_;
  mutable Vec3Array candidate_x_;  // the nodes when the list was made, m
  mutable double candidate_slack_m_ = 0.0;
  std::vector<Contact> active_;
  double phi_l1_max_ = 0.0;  // the largest phi_l1 of the surface
  double carried_gap_m_ = 0.0;
};

}  // namespace vascsim
