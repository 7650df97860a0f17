#pragma once
// A Simulation assembles a validated Scene into geometry -> discretisation -> energy -> problem ->
// model (by name, from the registry), and measures the named regions, probes and tools at every output
// point. It knows nothing of files or terminals (runner.hpp, output_writer.hpp).

#include <chrono>
#include <functional>
#include <memory>
#include <optional>

#include "vascsim/geometry/vessel_body.hpp"
#include "vascsim/mapping/mls_map.hpp"
#include "vascsim/model/model.hpp"
#include "vascsim/run/body_builder.hpp"
#include "vascsim/run/contact_surface_builder.hpp"
#include "vascsim/run/region_builder.hpp"
#include "vascsim/run/region_report.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim {

/// A rigid obstacle at one output point, with the names and meanings of summary.json's tools.
struct ObstacleMeasure {
  double displacement_m = 0.0;         ///< s |motion|, m
  Vec3 force_vector_n = Vec3::Zero();  ///< force the obstacle exerts on the tissue, N
  double force_n = 0.0;  ///< force_vector_n along the motion (its magnitude for a fixed obstacle), N
  Vec3 torque_vector_n_m =
      Vec3::Zero();  ///< moment of force_vector_n about the tool point (the catheter tip), N m
  int contacts = 0;  ///< nodes in contact
};

/// Everything measured at one output point.
struct StepRecord {
  int step = 0;  ///< 0 is the rest state
  StepReport report;
  std::vector<RegionMeasure> regions;      ///< in scene order
  std::vector<double> probes;              ///< point probe displacements, m, in scene order
  std::vector<ObstacleMeasure> obstacles;  ///< in scene order
  double wall_s = 0.0;                     ///< wall-clock time of this step, s
};

/// Checks a driver runs while a Simulation is built, to stop (throw) before the expensive stages.
struct BuildChecks {
  /// After the body is built (its node count and extent are known), before the discretisation.
  std::function<void(const Body&)> after_body;
};

class Simulation {
 public:
  explicit Simulation(const Scene& scene, const BuildChecks& checks = {});

  const Scene& scene() const { return scene_; }
  const Discretization& discretization() const { return *disc_; }
  const PointPrimitiveEnergy& energy() const { return *energy_; }
  const Problem& problem() const { return *problem_; }
  const Body& body() const { return *body_; }
  /// The MLS surface map; built on first use (null when the body has no surface).
  const MlsMap* surface_map();
  /// Maps the current node positions to the render surface (needs a surface).
  SurfaceFrame surface_frame();
  Model& model() { return *model_; }
  double setup_seconds() const { return setup_s_; }
  /// What every region selected beside what the scene asked (region_report.hpp), in scene order.
  const std::vector<RegionSelection>& region_selections() const { return selections_; }
  /// What the embedded contact's surface holds (contact.surface "embedded"; empty otherwise).
  const std::optional<ContactSurfaceReport>& contact_surface_report() const { return contact_report_; }

  /// The rest state (step 0).
  StepRecord initial_record() const;
  /// Advances the model to output point k (1..num_steps) and measures it. Throws NumericalError naming the
  /// step when the state has inverted material (model/inversion_check.hpp).
  StepRecord advance(int k);
  /// Throws NumericalError("<model>: <where>: ...") when the model's state has inverted material; in a scene
  /// with tools it warns (the first time) and counts instead (inverted_steps()): contact folds the lattice
  /// under a tool's rim.
  void check_state(const std::string& where);
  /// Checks that found inverted material under a tool's contact.
  int inverted_steps() const { return inverted_steps_; }
  /// Measures the current state as output point `step` (0: the rest state, no tool loads) with the model's
  /// `report`: what advance() does after the model moved; a driver that steps a DeviceDrivenModel itself (the
  /// Python module) measures its frames with it.
  StepRecord measure(int step, const StepReport& report) const;
  /// Reference values of the scene (e.g. the Timoshenko deflection), for summary.json; null if none.
  nlohmann::json reference(const StepRecord& last) const;

 private:
  void build(const BuildChecks& checks);
  void check_motion_sizes() const;

  Scene scene_;
  std::unique_ptr<Body> body_;
  std::unique_ptr<MlsMap> surface_map_;
  std::optional<ContactSurfaceReport> contact_report_;
  std::unique_ptr<Discretization> disc_;
  std::unique_ptr<PointPrimitiveEnergy> energy_;
  std::unique_ptr<Problem> problem_;
  std::unique_ptr<Model> model_;
  std::vector<Index> probe_nodes_;
  std::vector<RegionSelection> selections_;
  double setup_s_ = 0.0;
  int inverted_steps_ = 0;
};

}  // namespace vascsim
