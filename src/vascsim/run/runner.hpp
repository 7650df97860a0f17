#pragma once
// Headless run of a scene: drives a Simulation through every output point and writes, through the
// OutputWriter, probes.csv (a row per output point, flushed as it goes), the optional VTK series
// (vtk/nodes_NNNN.vtu + vtk/nodes.pvd, vtk/surface_NNNN.vtu + vtk/surface.pvd) and summary.json.

#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>

#include "vascsim/run/simulation.hpp"

namespace vascsim {

struct RunOptions {
  std::filesystem::path out_dir;
  /// Called after every output point with (record, total steps).
  std::function<void(const StepRecord&, int)> on_step;
  /// Run while the simulation is built (e.g. a limit on the node count).
  BuildChecks checks;
  /// Called once the run is built, before its first step (e.g. to estimate its cost, or refuse it by
  /// throwing).
  std::function<void(Simulation&)> after_setup;
};

/// Runs the scene and returns summary.json's content (also written). Throws InputError / NumericalError.
/// summary.json's "warnings" lists what the run found suspicious (a tool that never touched the tissue, load
/// steps that did not converge with a tool in contact), each also logged as a warning.
/// After an interrupt (core/interrupt.hpp) it stops at the next step boundary: summary.json then has
/// "interrupted": true and the steps done so far.
nlohmann::json run_scene(const Scene& scene, const RunOptions& options);

/// What run_scene builds before its first step, with the same checks and errors: the simulation (body,
/// discretisation, regions, tools, the model's set-up) and, with output.surface, the surface map (an
/// InputError when the geometry has no surface). `vascsim check` builds a scene through this.
std::unique_ptr<Simulation> build_run(const Scene& scene, const BuildChecks& checks = {});

/// summary.json's description of the MLS surface map of a run (the body must have a surface).
nlohmann::json surface_map_info(Simulation& sim);

/// summary.json's description of a run: scene, model, discretisation sizes, solver parameters, threads.
nlohmann::json describe_run(const Scene& scene, Simulation& sim);

/// Column names of probes.csv for a scene.
std::vector<std::string> probe_columns(const Scene& scene);

}  // namespace vascsim
