#pragma once
// `xpbd`: the real-time pipeline of docs/model/19-position-based.md. Per step of length step_s (the haptic
// tick), n_sub substeps of length h = step_s / n_sub (Macklin et al. 2019, "Small Steps in Physics
// Simulation"), each:
//   free nodes:        v <- v + h f_ext/m ;  x_prev <- x ;  p <- x + h v
//   constrained nodes: p <- prescribed position (w = 0)
//   lambda <- 0 (once per substep: XPBD semantics, Macklin, Mueller, Chentanez 2016)
//   n_it times, projected Gauss-Seidel in graph-colour order (constraint_colouring.hpp; one colour's
//   constraints share no node and run in parallel):
//     elastic constraints, one of
//       (A) meshless_strain (default): the point-primitive SVK energy of every node as one 6-component
//           constraint c_i = Mandel(E_i) with compliance (V_i C^)^{-1}
//           (constraints/meshless_strain_constraint.hpp), solved as a 6x6 block, followed by the
//           zero-energy-mode stabiliser of node i (docs/model/09-volume-term-and-stabiliser.md section 9.2)
//           as K pair constraints r_ij = x_j - x_i - F_i X_ij with compliance 1/(c_i w_ij). The real-time
//           model is then the same energy as quasi_static and explicit, so its steady state converges to
//           theirs.
//       (B) tet_neo_hookean: the stable neo-Hookean pair (C_H, C_D) of every virtual tetrahedron (Macklin &
//           Mueller 2021), converging to the P1 tet solution instead (see docs/model/19-position-based.md
//           section 19.3).
//     optional, with physical compliance: tet-edge stretching constraints (paper Eqs. 13-17, stiffness
//       k_e = E_s l0) and per-spring barycentre energy constraints (docs/model/16-deviations.md, E11,
//       calibrated to a bulk modulus kappa_e). Both add stiffness on top of the elastic energy; off by
//       default.
//   v <- (p - x_prev)/h, v <- v exp(-c h) (mass-proportional damping), x <- p.
// External loads (gravity, region forces) and prescribed displacements scale with the load factor,
// ramped linearly in time like ExplicitModel. A fixed/displacement region with a release time is let go
// then: its nodes become free and keep the velocity of their prescribed motion.
//
// The force every constraint exerted over the last substep, sum_c lambda_c grad C_c / h^2 (N per node,
// docs/model/19-position-based.md), is kept per node (constraint_forces()), so supports and tools feel what
// the solver applied.

#include <array>
#include <string>
#include <vector>

#include "vascsim/model/constraint_colouring.hpp"
#include "vascsim/model/device_driven_model.hpp"
#include "vascsim/model/registry.hpp"
#include "vascsim/model/rigid_obstacle.hpp"

namespace vascsim {

enum class XpbdElastic {
  MeshlessStrain,  ///< docs/model/19-position-based.md (A): the point-primitive energy (default)
  TetNeoHookean    ///< docs/model/19-position-based.md (B): the virtual tetrahedra's neo-Hookean pair
};

struct XpbdSettings {
  double duration_s = 0.02;         ///< simulated time, s
  double ramp_time_s = 0.01;        ///< loads ramp linearly to full over this time, then hold (0: at once), s
  double output_interval_s = 1e-3;  ///< time between output points, s (rounded to whole steps)
  double step_s = 1e-3;             ///< step (haptic tick), s; split into `substeps`
  int substeps = 8;                 ///< n_sub per step
  int iterations = 2;               ///< n_it Gauss-Seidel sweeps per substep (docs/validation.md, xpbd table)
  double damping_per_s =
      10.0;  ///< mass-proportional damping c, 1/s (docs/model/12-equation-of-motion.md: 5-20)
  XpbdElastic elastic = XpbdElastic::MeshlessStrain;
  double stretch_modulus_pa = 0.0;  ///< E_s of the tet-edge stretching constraints, k_e = E_s l0 (0: off), Pa
  double energy_modulus_pa = 0.0;   ///< kappa_e of the per-spring barycentre constraints (0: off), Pa
};

/// Reads the `xpbd` block of a scene (docs/scene-format.md).
XpbdSettings read_xpbd_settings(JsonReader& block);

/// The registry entry (registry.cpp).
ModelEntry xpbd_model_entry();

class XpbdModel final : public Model, public DeviceDrivenModel {
 public:
  XpbdModel(const Problem& problem, const XpbdSettings& settings);
  std::string name() const override { return "xpbd"; }
  int num_steps() const override { return num_steps_; }
  StepReport advance(int k) override;
  const Vec3Array& positions() const override { return x_; }
  double load_factor() const override { return s_; }
  nlohmann::json info() const override;
  /// sum_c lambda_c grad C_c / h^2 per node over the last substep, N (also on prescribed nodes).
  const Vec3Array* constraint_forces() const override { return &f_constraint_; }
  /// Per obstacle: the force it exerted on the tissue over the last substep, sum lambda n / h^2 (N), its
  /// moment about the tool point and the nodes in contact.
  std::vector<ObstacleLoad> obstacle_loads() const override { return obstacle_load_; }
  DeviceDrivenModel* device_driven() override { return this; }

  /// Places tool o by a device pose (rigid_obstacle.hpp obstacle_posed) for the end of the next step;
  /// the substeps move it linearly from its previous pose (docs/model/22-contact.md section 22.1). From
  /// the first call on, the tool ignores its load-factor motion. Throws std::out_of_range for a bad o.
  void set_tool_pose(std::size_t o, const Vec3& position_m, const Eigen::Quaterniond& orientation) override;
  /// The geometry tool o had in the last substep.
  const constraints::Capsule& obstacle_geometry(std::size_t o) const { return obstacle_now_.at(o); }
  /// One step of step_s (n_sub substeps) from the current time, for drivers that pace the model
  /// themselves (the haptic session). advance() is a sequence of these.
  StepReport step() override;
  double time() const override { return t_; }
  double frame_length_s() const override { return step_; }
  std::vector<ObstacleLoad> tool_loads() const override { return obstacle_load_; }
  double step_length() const { return step_; }

  const Vec3Array& velocities() const { return v_; }
  double substep_length() const { return h_; }
  /// Tet option only: 0.5 Delta_min / c_s, above which the substep risks the shear instability, s.
  double shear_stability_estimate() const { return h_shear_limit_; }
  /// Colours of the elastic constraints (nodes for (A), tets for (B)).
  int num_colours() const { return elastic_colours_.num_colours(); }
  const Colouring& elastic_colouring() const { return elastic_colours_; }
  /// One substep to load factor s_next (public for tests and experiments).
  void substep(double s_next);

 private:
  double load_factor_at(double t) const;
  void setup_meshless();
  void update_node_weights();     // D_i and node_active_ from the current inverse masses
  void apply_releases(double t);  // frees the nodes of regions whose release time has come
  void setup_tets();
  void setup_edges();
  void setup_barycentre();
  void project_node(Index i);  // (A) strain block (or law energy) + stabiliser pairs of node i
  Mat3 svk_strain_correction(Index i,
                             const Mat3& F);  // (A), SVK: the 6x6 block; returns G (Delta p_k = w_k G d_k)
  Mat3 law_energy_correction(Index i,
                             const Mat3& F);        // (A), any law: one scalar energy constraint; returns G
  void project_stabiliser(Index i, const Mat3& F);  // stabiliser pairs of node i with fit F
  void project_tet(Index t);                        // (B)
  void project_edge(Index e);                       // stretching
  void project_barycentre(Index t);                 // four per-spring barycentre constraints of tet t
  void project_contacts();  // every node against every obstacle as placed for this substep
  void place_obstacles(double s, double fraction);  // obstacle_now_ at load factor s, fraction of the step
  template <class Project>
  void sweep(const Colouring& colours, Project&& project);

  const Problem& problem_;
  XpbdSettings settings_;
  double step_ = 0.0, h_ = 0.0, inv_h2_ = 0.0, h_shear_limit_ = 0.0;
  int num_steps_ = 0;
  long long substeps_done_ = 0;
  double t_ = 0.0, s_ = 0.0;
  double lame_lambda_ = 0.0, shear_modulus_ = 0.0;
  bool parallel_ = false;

  Vec3Array x_, v_, x_prev_, p_, f_ext_, f_constraint_;
  std::vector<double> inv_mass_;
  std::vector<char> prescribed_, released_;  // per node; per region
  Colouring elastic_colours_;

  // (A) meshless strain: per node D_i = sum_k w_k d_ik d_ik^T (1/(kg m^2)), multipliers (6 per node),
  // strain scale (1: Green strain, 2: the literal eps = F^T F - I), stabiliser multipliers (3 per pair).
  std::vector<Mat3> weighted_d_;
  std::vector<char> node_active_;  // false when the whole stencil is prescribed
  std::vector<double> node_lambda_, pair_lambda_;
  double strain_scale_ = 1.0;
  bool stabilise_ = false;
  const materials::HyperelasticLaw* law_ = nullptr;                // null: the SVK block
  const std::vector<materials::MaterialFrame>* frames_ = nullptr;  // per node, for laws that need one

  // (B) tets: rest D_m^{-1}, compliances (1/J), multipliers (C_H, C_D).
  std::vector<Mat3> dm_inv_;
  std::vector<double> alpha_h_, alpha_d_, tet_lambda_;

  // Stretching constraints on the tet edges.
  std::vector<std::array<Index, 2>> edges_;  // geometry/boundary.hpp Edge: (lo, hi)
  std::vector<double> edge_rest_, edge_compliance_, edge_lambda_;
  Colouring edge_colours_;

  // Contact: multipliers per (node, obstacle) and the force on every obstacle's tissue side.
  std::vector<double> contact_lambda_;
  std::vector<ObstacleLoad> obstacle_load_;
  std::vector<constraints::Capsule> obstacle_now_, pose_from_, pose_to_;  // per obstacle
  std::vector<Vec3> tool_now_, tool_from_, tool_to_;                      // tool points, m
  std::vector<char> posed_;                                               // placed by set_obstacle_pose

  // Per-spring barycentre constraints (4 per tet).
  std::vector<std::array<double, 4>> bary_rest_;
  std::vector<double> bary_compliance_, bary_lambda_;
  Colouring tet_colours_;
};

}  // namespace vascsim
