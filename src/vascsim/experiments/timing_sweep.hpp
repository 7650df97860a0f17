#pragma once
// `vascsim experiment timing`: time per step and frames per second against node count for several models (the
// paper's Figs. 11-12: deformation time and frames of six models at several node counts). Every point is one
// model on one tube resolution (find_tube_resolution, as `vascsim bench`) with the same 1 ms step
// (timed_scene_overrides), the scene's loads ramping over the whole run (every timed step moves the
// indenter): `warmup_steps` untimed steps, then `steps` steps, each timed in two parts, the simulation
// (Model::advance, one 1 ms frame) and the surface map (the MLS map of the node displacements to the render
// surface, with normals, Simulation::surface_frame); each point reports their medians, steps per second = 1 /
// simulation and frames per second = 1 / (simulation + surface map), and the machine it ran on
// (machine_info.hpp).
//
// A point is an independent job: run_timing_point writes nothing, timing_point_json/from_json carry it to and
// from OUT/points/<model>-<target>.json, and merge_timing_points gathers a folder of them into one table, so
// a sweep can be fanned out (GNU parallel, a Slurm array) and merged afterwards (docs/replicate.md).

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace vascsim {

struct TimingSweepOptions {
  std::string scene_path = "scenes/vein-indent.json";
  std::vector<std::string> models = {"implicit",    "xpbd",    "mass_spring",     "fem_quasi_newton",
                                     "tensor_mass", "filling", "pbd_viscoelastic"};
  std::vector<int> target_nodes = {1000, 3000, 10000};
  int steps = 200;                     ///< timed steps per point (>= 1)
  int warmup_steps = 20;               ///< untimed steps before them (>= 0)
  int threads = 1;                     ///< OpenMP threads
  std::vector<std::string> overrides;  ///< --set path=value
  /// Called every few timed steps: (step, of steps).
  std::function<void(int, int)> on_step;
};

/// One model at one resolution. Times in ms, everything else SI.
struct TimingPoint {
  std::string model;
  int target_nodes = 0, nodes = 0, surface_vertices = 0, steps = 0, warmup_steps = 0, threads = 0;
  double node_spacing_m = 0.0, step_s = 0.0;
  double simulation_median_ms = 0.0, simulation_p10_ms = 0.0, simulation_p90_ms = 0.0;
  double surface_map_median_ms = 0.0;
  double steps_per_s = 0.0;                                 ///< 1000 / simulation_median_ms
  double frames_per_s = 0.0;                                ///< 1000 / (simulation + surface map medians)
  double setup_s = 0.0;                                     ///< building the Simulation, s
  double load_average_start = 0.0, load_average_end = 0.0;  ///< 1-minute load averages around the point
  nlohmann::json model_info;                                ///< Model::info() after the run
  nlohmann::json machine;                                   ///< machine_info() at the start
};

/// Runs one point. Throws InputError for a model that is not dynamic, a scene without a tube, bad counts.
TimingPoint run_timing_point(const TimingSweepOptions& options, const std::string& model, int target_nodes);

nlohmann::json timing_point_json(const TimingPoint& point);
TimingPoint timing_point_from_json(const nlohmann::json& j);

/// "<model>-<target>.json".
std::string timing_point_file(const std::string& model, int target_nodes);

/// Every points/*.json under `dir`, sorted by model (in `models` order when listed there) and node count.
std::vector<TimingPoint> merge_timing_points(const std::string& dir, const std::vector<std::string>& models);

/// The CSV of the merged points (column names carry their units).
std::string timing_csv(const std::vector<TimingPoint>& points);
/// A fixed-width table for the terminal.
std::string timing_table(const std::vector<TimingPoint>& points);

}  // namespace vascsim
