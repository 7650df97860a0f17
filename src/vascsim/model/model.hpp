#pragma once
// The Model interface: a solver that advances a Problem through a sequence of output points
// (load steps or output times). Models are chosen by name in the scene (registry.hpp); a model a device can
// drive also implements DeviceDrivenModel (device_driven_model.hpp).

#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "vascsim/model/problem.hpp"
#include "vascsim/model/rigid_obstacle.hpp"

namespace vascsim {

/// What one advance() did.
struct StepReport {
  double time_s = 0.0;       ///< simulated time at the output point (0 for quasi-static)
  double load_factor = 0.0;  ///< s in [0, 1]
  int iterations = 0;        ///< Newton iterations (quasi_static) or substeps (explicit)
  int inner_iterations = 0;  ///< conjugate-gradient iterations (quasi_static)
  double residual = 0.0;     ///< relative force residual (quasi_static); 0 otherwise
  bool converged = true;
};

class DeviceDrivenModel;

class Model {
 public:
  virtual ~Model() = default;
  virtual std::string name() const = 0;
  /// Number of output points the run produces.
  virtual int num_steps() const = 0;
  /// Advances to output point k (1-based, called in order).
  virtual StepReport advance(int k) = 0;
  /// Current node positions, m.
  virtual const Vec3Array& positions() const = 0;
  /// Load factor at the last output point.
  virtual double load_factor() const = 0;
  /// Solver parameters as used (dt, tolerances, stability limits), for summary.json.
  virtual nlohmann::json info() const = 0;
  /// The force (N per node) the model's elastic terms and constraints exerted on every node over the last
  /// substep, for reaction forces: position-based models return sum_c lambda_c grad C_c / h^2
  /// (docs/model/19-position-based.md), so a support or a tool feels exactly what the solver applied. nullptr
  /// (the default): the caller evaluates the point-primitive energy's forces at positions() instead (exact
  /// for force-based models).
  virtual const Vec3Array* constraint_forces() const { return nullptr; }
  /// Per rigid obstacle of the scene (in scene order): the force it exerted on the tissue (over the last
  /// substep for dynamic models, at equilibrium for quasi_static), its moment and contacts. Empty for
  /// models without obstacles.
  virtual std::vector<ObstacleLoad> obstacle_loads() const { return {}; }
  /// The device-driven view of this model (haptic sessions, the viewer); nullptr for models a device cannot
  /// drive. Agrees with the registry's capabilities.device_driven.
  virtual DeviceDrivenModel* device_driven() { return nullptr; }
};

}  // namespace vascsim
