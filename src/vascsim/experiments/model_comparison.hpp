#pragma once
// `vascsim experiment force-displacement SCENE --models a,b,...`: the force-displacement experiment
// (force_displacement.hpp) of one scene with several models, against a reference model (the paper's Fig. 10:
// six models on the hand dorsal vein; ours against the converged quasi_static curve of the same scene).
//
// Every model runs the single-model experiment into OUT/<model>/ (summary.json, force_displacement.csv, ...),
// so each model is an independent job: with `reuse`, a model whose OUT/<model>/summary.json holds a finished
// curve is read instead of run (run the models as separate `vascsim` processes, e.g. by GNU parallel or a
// Slurm array, then once more with --reuse to merge; docs/replicate.md). Then:
//   OUT/force_displacement_models.csv  model, displacement_m (m), force_n (N): every curve, long format
//   OUT/rms_error.csv and rms_error.json per model: the RMS difference to the reference curve (N and relative
//   to
//                                      the reference's largest force), the force at the deepest point, wall
//                                      time
//   OUT/force_displacement_models.png  every curve, the reference drawn thick
//   (scripts/plot_force_displacement.py)
// The error is taken at each model's own displacements in (0, reference's deepest point], the reference
// interpolated linearly between its converged load steps; where a dynamic model reports one displacement
// several times (a held press) its last, settled value is used. Curves are read from OUT/<model>/
// force_displacement.csv (after a run as on reuse).

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "vascsim/run/simulation.hpp"

namespace vascsim {

struct ModelComparisonOptions {
  std::filesystem::path out_dir;
  std::vector<std::string> models;  ///< the reference need not be listed
  std::string reference = "quasi_static";
  std::vector<std::string> overrides;  ///< --set path=value, applied to every model's scene
  std::string tool;                    ///< empty: the scene's only tool
  bool reuse = false;                  ///< read finished models from OUT/<model>/ instead of running them
  bool plot = true;
  std::string python = "/usr/bin/python3";
  std::function<void(const std::string& model, const StepRecord&, int total)> on_step;
  std::function<void(const std::string& line)> progress;
};

/// One model's curve and its error against the reference.
struct ModelCurve {
  std::string model;
  std::vector<double> displacement_m, force_n;
  std::vector<char> converged;  ///< per point (the reference's non-converged points are not compared against)
  double rms_error_n = 0.0;     ///< RMS of F - F_ref over the compared points, N
  double rms_relative = 0.0;    ///< rms_error_n / max |F_ref|
  double rms_percent = 0.0;     ///< 100 rms_error_n / RMS(F_ref at the same points): docs/ahp.md's I7 figure
  double max_force_n = 0.0;     ///< the force at the deepest compared point, N
  double max_force_ratio = 0.0;  ///< that force over the reference's there
  int points = 0;                ///< compared points
  double wall_s = 0.0;           ///< the run's wall time (0 when reused and unknown), s
  int nodes = 0;
  bool reused = false;
};

struct ModelComparisonResult {
  std::vector<ModelCurve> curves;  ///< the reference first
  std::filesystem::path csv, rms_csv, rms_json, png;
  std::string plot_problem;
};

/// Runs (or reuses) every model and writes the comparison. Throws InputError for an empty model list, an
/// unknown model, or a scene without a moving tool.
ModelComparisonResult run_model_comparison(const std::string& scene_path,
                                           const ModelComparisonOptions& options);

/// The RMS error and end-force ratio of `curve` against `reference`'s converged points (filled in `curve`).
void compare_to_reference(const ModelCurve& reference, ModelCurve& curve);

/// `curve` without its points that did not converge.
ModelCurve converged_points(const ModelCurve& curve);

/// A fixed-width table of the comparison for the terminal.
std::string model_comparison_table(const ModelComparisonResult& result);

}  // namespace vascsim
