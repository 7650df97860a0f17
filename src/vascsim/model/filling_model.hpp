#pragma once
// `filling`: the "filling model" of
//   X. F. Ye, X. K. Mei, S. G. Xiao, "Filling model based soft tissue deformation model", Proc. ICMA 2018,
//   Changchun, China, pp. 1655-1659 (the paper's baseline [27]).
// INTERPRETATION (docs/model/25-baselines.md section 25.5): nothing of that paper could be retrieved beyond
// its citation; the same group's vessel model uses PBD with a volume-conservation constraint. We read
// "filling" as a closed surface filled with a lattice of particles, held by springs and by the volume they
// enclose:
//   particles: the point-primitive nodes, which fill the body (the wall) on a lattice; the surface vertices
//   are
//     lattice particles too, so the tethers from the surface to the fill coincide with the lattice edges
//     between the surface layer and the next one;
//   structural and shear springs: every lattice (virtual tet) edge, an XPBD distance constraint with
//   compliance
//     1/k_e, k_e = E sum_{T contains e} V_T / |e|^2 (spring_network.hpp: the network's Young's modulus is E);
//   one global volume constraint C = sum_T V_T(x) - V_0 with compliance V_0 / (K - 2E/3) (the bulk modulus
//   the
//     nu = 1/4 network lacks; none when nu <= 1/4);
//   XPBD with substeps (Macklin et al. 2019) as in xpbd: per substep h = frame / substeps, v += h f_ext/m,
//   p = x + h v, `iterations` Gauss-Seidel sweeps of the springs and the volume, tools, v = (p - x)/h e^{-c
//   h}.

#include "vascsim/model/dynamic_baseline.hpp"
#include "vascsim/model/spring_network.hpp"

namespace vascsim {

struct FillingSettings {
  BaselineFrames frames;
  int substeps = 8;             ///< per frame
  int iterations = 2;           ///< Gauss-Seidel sweeps per substep
  double damping_per_s = 10.0;  ///< mass-proportional damping c, 1/s
};

FillingSettings read_filling_settings(JsonReader& block);
ModelEntry filling_model_entry();

class FillingModel final : public DynamicBaseline {
 public:
  FillingModel(const Problem& problem, const FillingSettings& settings);
  /// sum_T V_T(x) of the current positions, m^3.
  double enclosed_volume() const;

 protected:
  StepReport frame(double s_prev, double s_next) override;
  nlohmann::json method_info() const override;

 private:
  void substep(double s, double weight);
  void project_volume(double weight);
  FillingSettings settings_;
  SpringNetwork lattice_;
  std::vector<double> mass_, inv_mass_, spring_lambda_;
  double rest_volume_ = 0.0, volume_compliance_ = 0.0, volume_lambda_ = 0.0, dt_ = 0.0;
  Vec3Array f_ext_, x_old_, grad_;
};

}  // namespace vascsim
