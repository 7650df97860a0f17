#pragma once
// `pbd_viscoelastic`: viscoelastic mass-spring-dampers inside position-based dynamics, after
//   L. Xu, Y. H. Lu, Q. Liu, "Integrating viscoelastic mass spring dampers into position-based dynamics to
//   simulate soft tissue deformation in real time", Royal Society Open Science 5(2), 171587, 2018 (the
//   paper's baseline [16]).
// INTERPRETATION (docs/model/25-baselines.md section 25.6): only the paper's abstract could be established
// (the MSD force is made nonlinear and viscoelastic, used with the PBD projection, nodes driven by "spring
// force + constraint force" through Newton's second law, incompressibility enforced); the equations below are
// ours.
//
// Nodes and masses are the point-primitive nodes (tet-partition masses). Per substep dt:
//   f = f_ext + sum of the Kelvin-Voigt springs on every tet edge (spring_network.hpp):
//       k(l) = k0 (1 + a ((l - l0)/l0)^2),  k0 = E sum_{T contains e} V_T / |e|^2,  c = 2 zeta sqrt(k0 m_ab)
//   v += dt f / m,  p = x + dt v                         (the MSD forces, semi-implicit Euler)
//   `iterations` Gauss-Seidel sweeps of the XPBD tet volume constraints C_T = V_T - V_T0 with compliance
//   alpha_T = V_T0 / (K - K_net): the springs alone have the bulk modulus K_net = 2E/3 of a nu = 1/4 network;
//   the constraints add what the material's K = E / (3 (1 - 2 nu)) lacks (none when nu <= 1/4)
//   tools (dynamic_baseline.hpp), then v = (p - x)/dt, x = p.
// dt = safety * 2/(omega + gamma) from the springs' Gershgorin bounds (the volume constraints are
// unconditionally stable), whole substeps per frame.

#include "vascsim/model/dynamic_baseline.hpp"
#include "vascsim/model/spring_network.hpp"

namespace vascsim {

struct PbdViscoelasticSettings {
  BaselineFrames frames;
  double nonlinearity = 2.0;      ///< a in k(l) = k0 (1 + a strain^2)
  double damping_ratio = 0.05;    ///< zeta of every spring's dashpot (the Kelvin-Voigt viscosity)
  double damping_per_s = 0.0;     ///< mass-proportional damping, 1/s
  int iterations = 2;             ///< volume-constraint sweeps per substep
  double time_step_safety = 0.5;  ///< fraction of the Gershgorin stability limit
  double max_strain = 0.3;        ///< the strain the stability bound allows for the nonlinear springs
};

PbdViscoelasticSettings read_pbd_viscoelastic_settings(JsonReader& block);
ModelEntry pbd_viscoelastic_model_entry();

class PbdViscoelasticModel final : public DynamicBaseline {
 public:
  PbdViscoelasticModel(const Problem& problem, const PbdViscoelasticSettings& settings);
  double substep_s() const { return dt_; }
  int substeps_per_frame() const { return substeps_; }

 protected:
  StepReport frame(double s_prev, double s_next) override;
  nlohmann::json method_info() const override;

 private:
  void substep(double s, double weight);
  PbdViscoelasticSettings settings_;
  SpringNetwork springs_;
  std::vector<double> mass_, inv_mass_, rest_volume_, tet_lambda_;
  double volume_compliance_per_m3_ = 0.0;  // alpha_T / V_T0 = 1 / (K - K_net), 1/Pa; 0: no constraints
  double dt_ = 0.0;
  int substeps_ = 1;
  Vec3Array f_, f_ext_, x_old_;
};

}  // namespace vascsim
