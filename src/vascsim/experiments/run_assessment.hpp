#pragma once
// What a built run is expected to cost and how far off its forces may be, before it is solved: the number of
// model steps it will take, its cost from the machine's calibration (cost_model.hpp), and warnings for models
// known to be far off at the scene's settings (force_accuracy.hpp). `vascsim run` logs these before the first
// step; `vascsim check` prints them.

#include <optional>
#include <string>
#include <vector>

#include "vascsim/experiments/cost_model.hpp"
#include "vascsim/experiments/force_accuracy.hpp"
#include "vascsim/run/simulation.hpp"

namespace vascsim {

/// The model steps a headless run of `sim` takes: its load steps (load-stepped models), or the duration over
/// the step length the calibration names for the model (dynamic models; its output points without one).
double headless_model_steps(const Scene& scene, Simulation& sim, const ModelCost* cost);

/// The expected cost of a built run with `steps` model steps; nullopt when the model is not calibrated.
std::optional<CostEstimate> estimate_run_cost(const CostCalibration& calibration, const Scene& scene,
                                              Simulation& sim, double steps);

/// The scene's own warnings (Scene::warnings: implausible sizes, a lattice coarse for its wall, node contact
/// by node_radius_m), then one line per rule of the table the scene's model breaks (e.g. xpbd with a large
/// per-substep stiffness ratio), and linear_fit_layers_warning's line.
std::vector<std::string> model_accuracy_warnings(const ForceAccuracyTable& table, const Scene& scene,
                                                 Simulation& sim);

/// The linear fit with the layers reach on a wall of four or more node layers is stiff (docs/validation.md,
/// "Layers through the wall": a surface node's fit sees fewer layers than the wall has): the warning, or ""
/// where it does not apply.
std::string linear_fit_layers_warning(const Scene& scene, const Simulation& sim);

/// The calibration and the accuracy table of this source tree, read once; nullptr (with a debug log line)
/// when a file is missing or malformed, so a run never fails for want of them.
const CostCalibration* bundled_cost_calibration();
const ForceAccuracyTable* bundled_force_accuracy();

}  // namespace vascsim
