#pragma once
// `mass_spring`: the surface mass-spring model with flexion springs of
//   C. Q. Li, J. J. Ding, Z. C. Hong, Y. C. Pan, P. X. Liu, "A surface mass-spring model with new flexion
//   springs and collision detection algorithms based on volume structure for real-time soft-tissue
//   deformation interaction", IEEE Access 6, pp. 75572-75597, 2018 (the paper's baseline [8]),
// as far as it could be established (docs/model/25-baselines.md section 25.2; the flexion-spring stiffness is
// our interpretation).
//
// The nodes are the vertices of the body's closed surface, the boundary triangles of the virtual tetrahedra
// (on a vessel: the outer and inner wall and the two end annuli). That surface is a shell of thickness t_s =
// V / A (the body's volume over its surface area: it carries the body's whole mass, t/2 per sheet on a wall
// of thickness t), masses m_i = rho t_s A_i (lumped area). Springs (spring_network.hpp):
//   structural, on every surface edge:  k_e = E t_s sum_{T contains e} A_T / |e|^2       (Van Gelder)
//   damping per spring c = 2 zeta sqrt(k m_a m_b / (m_a + m_b)), and mass-proportional damping c_m;
//   flexion (bending), on every surface edge: an angular spring on the dihedral angle of its two triangles
//   (constraints/dihedral_angle.hpp), U = k_b (theta - theta_0)^2 / 2, f = -k_b (theta - theta_0) grad theta,
//   with the discrete-shell stiffness k_b = flexion_scale D |e|^2 / A_e, D = E t_s^3 / (12 (1 - nu^2)), A_e =
//   (A_1 + A_2)/3 (Grinspun, Hirani, Desbrun, Schroeder, "Discrete shells", SCA 2003) [interpretation of
//   [8]'s "flexion springs", whose equations could not be retrieved].
// Semi-implicit (symplectic) Euler, v += dt (f + f_ext)/m, x += dt v, with dt = safety * 2/(omega + gamma)
// from Gershgorin bounds of the springs and hinges at rest (whole substeps per frame). Tools: surface nodes
// that enter a tool are put back on its surface (dynamic_baseline.hpp).
//
// The other nodes (inside the wall) carry no mass: their displacement is the inverse-distance (Shepard) mean
// of their `map_neighbours` nearest surface nodes', and loads on them (gravity, region forces) are passed to
// those surface nodes by the transposed weights, so the output (regions, probes, the MLS surface map) sees
// every node.

#include "vascsim/model/dynamic_baseline.hpp"
#include "vascsim/model/spring_network.hpp"

namespace vascsim {

struct MassSpringSettings {
  BaselineFrames frames;
  double shell_thickness_m = 0.0;  ///< t_s (0: V / A of the body), m
  double flexion_scale = 1.0;      ///< factor on the flexion (bending) rule (0: no flexion springs)
  double damping_ratio = 0.05;     ///< zeta of every spring's dashpot
  double damping_per_s = 0.0;      ///< mass-proportional damping c_m, 1/s
  double time_step_safety = 0.5;   ///< fraction of the Gershgorin stability limit
  int map_neighbours = 4;          ///< surface nodes each inner node follows
};

MassSpringSettings read_mass_spring_settings(JsonReader& block);
ModelEntry mass_spring_model_entry();

class MassSpringModel final : public DynamicBaseline {
 public:
  MassSpringModel(const Problem& problem, const MassSpringSettings& settings);
  /// The substep, s.
  double substep_s() const { return dt_; }
  int substeps_per_frame() const { return substeps_; }
  /// Per node: 1 if it is a surface (mass-spring) node.
  const std::vector<char>& surface_nodes() const { return on_surface_; }
  const SpringNetwork& springs() const { return springs_; }
  double shell_thickness() const { return thickness_; }
  /// sum of the surface masses, kg.
  double total_mass() const;

 protected:
  StepReport frame(double s_prev, double s_next) override;
  nlohmann::json method_info() const override;

 private:
  struct Hinge {
    Index x1, x2, x3, x4;  // opposite vertices, then the edge (dihedral_angle.hpp)
    double theta0, k;      // rest angle (rad), stiffness (N m / rad^2)
  };
  void build_springs(const std::vector<Triangle>& faces);
  void add_hinge_forces(const Vec3Array& x, Vec3Array& f) const;
  void add_hinge_rows(std::vector<double>& k_rows) const;
  void build_map();
  void map_inner(double s);

  MassSpringSettings settings_;
  std::vector<char> on_surface_;
  std::vector<double> mass_;
  SpringNetwork springs_;
  std::vector<Hinge> hinges_;
  double thickness_ = 0.0, dt_ = 0.0;
  int substeps_ = 1, structural_ = 0, flexion_ = 0;
  // Inner nodes: CSR rows of (surface node, weight).
  std::vector<Index> inner_, map_start_, map_node_;
  std::vector<double> map_weight_;
  Vec3Array f_, f_ext_;
};

}  // namespace vascsim
