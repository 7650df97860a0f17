#pragma once
// The real-time benchmark behind `vascsim bench`: wall time per 1 ms simulated step of a dynamic model
// (default `xpbd`) on a tube scene (default the vein) at several resolutions and OpenMP thread counts,
// reported against the haptic target (1 ms of simulated time in <= 1 ms of wall time at >= 2,000 nodes)
// and the visual one (>= 85 steps per second at >= 20,000 nodes), both on 2 cores.
// Each configuration builds a fresh Simulation, runs `warmup_steps` untimed steps (the scene's load ramps
// in), then times `steps` calls of Model::advance, each exactly one 1 ms step. Only the model is timed,
// not Simulation::advance's measurements. Timing is reported, never asserted.

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "vascsim/scene/scene.hpp"

namespace vascsim {

struct RealtimeBenchOptions {
  std::string scene_path = "scenes/vein-indent.json";
  std::string model = "xpbd";  ///< "xpbd" or "explicit" (the dynamic models with benchmark settings)
  std::vector<int> target_nodes = {1000, 3000, 10000, 30000};
  std::vector<int> threads = {1, 2};
  int steps = 200;                     ///< timed steps per configuration (>= 1)
  int warmup_steps = 20;               ///< untimed steps before them (>= 0)
  std::vector<std::string> overrides;  ///< --set path=value, applied before the benchmark's own keys
  /// One line per finished configuration (and per resolution found); nullptr: silent.
  std::function<void(const std::string&)> progress;
};

/// One (resolution, thread count) configuration. Times in ms (report columns), everything else SI.
struct RealtimeBenchRow {
  int target_nodes = 0;
  int nodes = 0;
  double node_spacing_m = 0.0;
  double mean_neighbours = 0.0;  ///< K, the stencil size of the meshless strain constraint minus one
  int threads = 0;
  int substeps = 0;               ///< per 1 ms step
  std::optional<int> iterations;  ///< solver sweeps per substep (xpbd); none for explicit
  int warmup_steps = 0;
  int steps = 0;
  double median_ms = 0.0, p10_ms = 0.0, p90_ms = 0.0, mean_ms = 0.0, max_ms = 0.0;
  double steps_per_s = 0.0;      ///< 1000 / median_ms
  double realtime_factor = 0.0;  ///< simulated time / wall time at the median
  bool meets_haptic = false;     ///< median <= 1 ms
  bool meets_visual = false;     ///< >= 85 steps/s
  double setup_s = 0.0;          ///< building the Simulation (geometry .. model), not timed per step
  nlohmann::json model_info;     ///< Model::info() after the run
};

struct RealtimeBenchReport {
  nlohmann::json header;  ///< machine, build, date, scene, model, settings, targets and verdicts
  std::vector<RealtimeBenchRow> rows;
};

/// The tube spacing whose node count is nearest to a target.
struct TubeResolution {
  double node_spacing_m = 0.0;
  int nodes = 0;
};

/// The step every benchmark advance() covers (the haptic tick), s.
inline constexpr double kBenchStepS = 1e-3;
/// A resolution farther than this (relative) from its target is reported with a warning.
inline constexpr double kBenchNodeTolerance = 0.10;

/// Three node layers through the wall, the real-time scenes' count, whatever the scene asks (a user's --set
/// wins): the timing sweeps go down to a few hundred nodes, where four layers under 8 columns are too flat
/// for any support (the bundled quasi_static wall scenes have four), and the timings stay comparable with
/// those recorded before.
inline constexpr const char* kBenchLayersOverride = "geometry.min_layers=3";

/// The scene keys that make a tube scene a timing case: the benchmark's defaults (more support growths for
/// coarse vein clouds, kBenchLayersOverride), then the user's overrides, then model=`model`, the spacing,
/// output_interval_s = one 1 ms step, duration_s = total_steps steps, and the model's ramp kept but finished
/// within the run (these win).
std::vector<std::string> timed_scene_overrides(const std::string& model, const std::vector<std::string>& user,
                                               int total_steps, double ramp_s, double spacing_m);

/// Bisects geometry.tube.node_spacing_m (building only the node cloud) for the node count nearest to
/// `target_nodes`. The count is a non-increasing step function of the spacing; at coarse spacings the
/// wall keeps min_layers radial layers, so it falls more slowly there. Throws InputError for a non-tube
/// geometry or a non-positive target.
TubeResolution find_tube_resolution(const GeometrySpec& geometry, int target_nodes);

/// Runs the benchmark. Throws InputError for bad options (unknown or static model, counts < 1, a scene
/// without a tube), NumericalError if a run diverges. Restores the OpenMP thread count on return.
RealtimeBenchReport run_realtime_bench(const RealtimeBenchOptions& options);

/// The whole report as JSON: {"header": ..., "results": [...]} (results carry model_info too).
nlohmann::json realtime_bench_json(const RealtimeBenchReport& report);
/// One CSV line per configuration, with a header line (column names carry their units).
std::string realtime_bench_csv(const RealtimeBenchReport& report);
/// A fixed-width table and the verdicts against the targets, for the terminal.
std::string realtime_bench_table(const RealtimeBenchReport& report);

}  // namespace vascsim
