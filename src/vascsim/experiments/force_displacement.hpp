#pragma once
// `vascsim experiment force-displacement SCENE.json`: a tool (the catheter) presses the vessel wall in
// displacement steps and the force it feels is written against its displacement (the paper's Fig. 10
// set-up is scenes/hand-dorsal-vein-catheter.json). The scene's model decides how: quasi_static solves the
// frictionless contact to equilibrium at every step (the accurate curve), xpbd presses dynamically at the
// haptic rate (what a trainee feels; too soft on thin walls, docs/validation.md).
//
// Writes into the output folder everything `vascsim run` writes (summary.json, probes.csv, VTK) plus
// force_displacement.csv and, with Debian's matplotlib, force_displacement.png
// (scripts/plot_force_displacement.py).

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "vascsim/run/simulation.hpp"

namespace vascsim {

struct ForceDisplacementOptions {
  std::filesystem::path out_dir;
  std::string tool;  ///< obstacle name; empty: the scene's only obstacle
  bool plot = true;
  std::string python = "/usr/bin/python3";
  /// Default: the bundled scripts/plot_force_displacement.py (core/bundled_files.hpp).
  std::filesystem::path plot_script;
  std::function<void(const StepRecord&, int)> on_step;
};

struct ForceDisplacementResult {
  nlohmann::json summary;     ///< summary.json of the run, with a "force_displacement" entry
  std::filesystem::path csv;  ///< force_displacement.csv
  std::filesystem::path png;  ///< empty if not plotted
  std::string plot_problem;   ///< why there is no PNG (empty if plotted or not asked for)
};

/// Throws InputError if the scene has no such tool, or the tool does not move.
ForceDisplacementResult run_force_displacement(const Scene& scene, const ForceDisplacementOptions& options);

/// The columns of force_displacement.csv. displacement_m is the tool's travel along its push (m); force_n is
/// summary.json's and probes.csv's: the force the tool exerts on the tissue along its push, N (positive while
/// it presses; the tissue resists the tool with as much). force_x_n .. force_z_n and torque_x_n_m ..
/// torque_z_n_m are the force and torque the tissue exerts on the tool (N, N m about the tool point), as in
/// force_history.csv.
std::vector<std::string> force_displacement_columns();

}  // namespace vascsim
