#pragma once
// `explicit`: symplectic Euler on the point-primitive forces (docs/model/12-equation-of-motion.md), the
// verification reference. The substep is chosen automatically below the stability limit of
// docs/model/12-equation-of-motion.md: dt = min(safety * 2 / (1.05 omega_max), C * Delta_min / c_p), with
// mass-proportional damping v <- v exp(-c dt). Paper Eq. 10 with the sign fixed (E6): a = (f_ext + f_int) /
// m.

#include "vascsim/model/model.hpp"
#include "vascsim/model/registry.hpp"

namespace vascsim {

struct ExplicitSettings {
  double duration_s = 0.02;         ///< simulated time, s
  double ramp_time_s = 0.01;        ///< loads ramp linearly to full over this time, then hold (0: at once), s
  double output_interval_s = 1e-3;  ///< time between output points, s
  double damping_per_s =
      10.0;             ///< mass-proportional damping c, 1/s (docs/model/12-equation-of-motion.md: 5-20)
  double dt_s = 0.0;    ///< substep; 0 = automatic. Must not exceed 2/(1.05 omega_max)
  double safety = 0.5;  ///< automatic dt = safety * 2/omega_max (docs/model/12-equation-of-motion.md rule)
  double cfl_coefficient = 0.4;    ///< and dt <= C Delta_min / c_p (halved with the literal strain)
  int power_iterations = 60;       ///< power iterations for omega_max
  bool eq10_literal_sign = false;  ///< a = (f_ext - f_int)/m as printed (negative test E6 only)
};

/// Reads the `explicit` block of a scene (docs/scene-format.md).
ExplicitSettings read_explicit_settings(JsonReader& block);

/// The registry entry (registry.cpp).
ModelEntry explicit_model_entry();

/// Symplectic Euler state and substep, usable on its own (tests, experiments).
class ExplicitIntegrator {
 public:
  ExplicitIntegrator(const Problem& problem, double dt_s, double damping_per_s,
                     bool eq10_literal_sign = false);
  /// One substep to load factor s_next: v += dt (f_int + f_ext)/m, v *= exp(-c dt), x += dt v;
  /// constrained nodes follow their prescribed positions.
  void substep(double s_next);
  Vec3Array& positions() { return x_; }
  const Vec3Array& positions() const { return x_; }
  Vec3Array& velocities() { return v_; }
  const Vec3Array& velocities() const { return v_; }
  const Vec3Array& internal_forces() const { return f_int_; }  ///< at the start of the last substep
  const Vec3Array& external_forces() const { return f_ext_; }
  double elastic_energy() const { return last_energy_; }  ///< at the start of the last substep, J
  double kinetic_energy() const;                          ///< 1/2 sum m |v|^2 (half-step velocities), J
  double dt() const { return dt_; }

 private:
  const Problem& problem_;
  double dt_, damping_;
  bool literal_sign_;
  Vec3Array x_, v_, f_int_, f_ext_;
  double last_energy_ = 0.0;
};

class ExplicitModel final : public Model {
 public:
  ExplicitModel(const Problem& problem, const ExplicitSettings& settings);
  std::string name() const override { return "explicit"; }
  int num_steps() const override { return num_steps_; }
  StepReport advance(int k) override;
  const Vec3Array& positions() const override { return integrator_->positions(); }
  double load_factor() const override { return s_; }
  nlohmann::json info() const override;
  const ExplicitIntegrator& integrator() const { return *integrator_; }

 private:
  double load_factor_at(double t) const;
  ExplicitSettings settings_;
  double omega_max_ = 0.0, dt_stability_ = 0.0, dt_cfl_ = 0.0, dt_ = 0.0;
  int num_steps_ = 0;
  long long substeps_done_ = 0;
  double t_ = 0.0, s_ = 0.0;
  std::unique_ptr<ExplicitIntegrator> integrator_;
};

}  // namespace vascsim
