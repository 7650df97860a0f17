#pragma once
// What the five comparison baselines of the paper's section 3.3 (mass_spring, fem_quasi_newton, tensor_mass,
// filling, pbd_viscoelastic; docs/model/25-baselines.md) have in common, so that each baseline file holds
// only its method: a time-stepping Model and DeviceDrivenModel over the problem's nodes with
//   - frames of length frame_s (the haptic tick, 1 ms by default), each advanced by the baseline's frame();
//   - loads, prescribed displacements and tool motion ramped in by the load factor as in xpbd and implicit
//     (TimeSchedule), or the tools posed by a device (ToolPlacement);
//   - the force the baseline's own elastic terms exert on every node (constraint_forces(), so supports report
//     the baseline's reaction, not the point-primitive energy's), and the load on every tool.
// A baseline's settings block has the three schedule keys and frame_s (read_baseline_frames) plus its own.
//
// Contact helper for the position-based and explicit baselines: project_tool_contacts() puts a free node that
// entered a tool back on its surface and books the impulse m dx / h^2 as the tool's force on the tissue (the
// xpbd contact with alpha = 0, docs/model/22-contact.md section 22.2). The implicit baselines hold contacts
// inside their solve (ContactActiveSet) instead.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "vascsim/model/contact_active_set.hpp"
#include "vascsim/model/device_driven_model.hpp"
#include "vascsim/model/registry.hpp"
#include "vascsim/model/tool_placement.hpp"

namespace vascsim {

/// The schedule keys every baseline block has, with frame_s.
struct BaselineFrames {
  TimeSchedule schedule;
  double frame_s = 1e-3;  ///< one frame (a DeviceDrivenModel step, the haptic tick), s
};

/// Reads duration_s, ramp_time_s, output_interval_s and frame_s from a baseline's block.
BaselineFrames read_baseline_frames(JsonReader& block);

/// The registry entry's common part: name, summary, capabilities (dynamic, tools, device-driven; no region
/// release), schedule. `frames_of` returns the BaselineFrames of the model's settings struct.
ModelEntry baseline_entry(const std::string& name, const std::string& summary,
                          std::function<BaselineFrames(const std::any&)> frames_of);

/// The whole entry of baseline model M with settings S (which has a `frames` member) read by `read`.
template <class M, class S>
ModelEntry make_baseline_entry(const std::string& name, const std::string& summary, S (*read)(JsonReader&)) {
  ModelEntry e = baseline_entry(name, summary, [](const std::any& s) { return settings_as<S>(s).frames; });
  e.read_settings = [read](JsonReader& block) { return std::any(read(block)); };
  e.make = [](const Problem& problem, const std::any& settings) -> std::unique_ptr<Model> {
    return std::make_unique<M>(problem, settings_as<S>(settings));
  };
  return e;
}

/// sum_i a_i . b_i over two per-node arrays of one size.
double dot(const Vec3Array& a, const Vec3Array& b);

class DynamicBaseline : public Model, public DeviceDrivenModel {
 public:
  DynamicBaseline(const Problem& problem, std::string name, const BaselineFrames& frames);

  std::string name() const override { return name_; }
  int num_steps() const override { return num_steps_; }
  StepReport advance(int k) override;
  const Vec3Array& positions() const override { return x_; }
  double load_factor() const override { return s_; }
  nlohmann::json info() const override;
  /// The force the baseline's elastic terms (springs, tets, constraints) exerted on every node in the last
  /// frame, N.
  const Vec3Array* constraint_forces() const override { return &f_int_; }
  std::vector<ObstacleLoad> obstacle_loads() const override { return loads_; }
  DeviceDrivenModel* device_driven() override { return this; }

  void set_tool_pose(std::size_t tool, const Vec3& position_m,
                     const Eigen::Quaterniond& orientation) override;
  StepReport step() override;
  double time() const override { return t_; }
  double frame_length_s() const override { return h_; }
  std::vector<ObstacleLoad> tool_loads() const override { return loads_; }

  const Vec3Array& velocities() const { return v_; }
  /// Frames advanced so far.
  long long frames() const { return frames_; }

 protected:
  /// Advances x_ and v_ by one frame of h_ to load factor s_next (from s_prev); sets f_int_ and loads_.
  /// Returns the frame's report (iterations: substeps or solver iterations; converged).
  virtual StepReport frame(double s_prev, double s_next) = 0;
  /// The baseline's own entries for info() (parameters as derived from E, nu, and the solver's).
  virtual nlohmann::json method_info() const = 0;

  /// Every free node with mass that entered a tool (placed at load factor s) is put back on the surface of
  /// the deepest one; weight * mass[i] dx / dt^2, the force that tool exerted on the tissue over the
  /// (sub)step, is added to its load in loads_ (the contact count is that of this call). A frame of n
  /// substeps calls it once per substep with weight 1/n after reset_loads(), so loads_ is the frame's mean.
  void project_tool_contacts(Vec3Array& x, const std::vector<double>& mass, double dt, double s,
                             double weight);
  void reset_loads();
  /// Zeroes v at the prescribed nodes and removes its normal component at the nodes in contact (the filter of
  /// Baraff & Witkin's modified PCG, contact_active_set.hpp), for the implicit baselines' solvers.
  void filter_free(Vec3Array& v, const ContactActiveSet& contacts) const;

  const Problem& problem_;
  std::string name_;
  BaselineFrames frames_settings_;
  double h_ = 0.0;
  Vec3Array x_, v_, f_int_;
  std::vector<ObstacleLoad> loads_;
  ToolPlacement tools_;

 private:
  double load_factor_at(double t) const;
  int num_steps_ = 0;
  double t_ = 0.0, s_ = 0.0;
  long long frames_ = 0, iterations_ = 0, unconverged_ = 0;
};

}  // namespace vascsim
