#pragma once
// Headless run of a scene: drives a Simulation through every output point and writes, into the
// output folder, probes.csv (a row per output point, flushed as it goes), the optional VTK series
// (vtk/nodes_NNNN.vtu + vtk/nodes.pvd) and summary.json.

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>

#include "vascsim/scene/simulation.hpp"

namespace vascsim {

struct RunOptions {
  std::filesystem::path out_dir;
  /// Called after every output point with (record, total steps).
  std::function<void(const StepRecord&, int)> on_step;
};

/// Runs the scene and returns summary.json's content (also written). Throws InputError / NumericalError.
nlohmann::json run_scene(const Scene& scene, const RunOptions& options);

/// Writes the MLS-mapped render surface of the current state to a .vtu file (the body must have a surface).
void write_surface_frame(Simulation& sim, const std::filesystem::path& file);

/// summary.json's description of a run: scene, model, discretisation sizes, solver parameters, threads.
nlohmann::json describe_run(const Scene& scene, Simulation& sim);

/// Column names of probes.csv for a scene.
std::vector<std::string> probe_columns(const Scene& scene);

}  // namespace vascsim
