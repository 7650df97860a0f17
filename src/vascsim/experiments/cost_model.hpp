#pragma once
// What a run will cost on this machine, from a calibration measured here (data/calibration/cost_model.json,
// written by scripts/calibrate_cost_model.py from timed `vascsim run`s of the bundled scenes at a few sizes):
// per model, the wall time of one model step (a load step of a load-stepped model, a frame or time step of a
// dynamic one) and the peak resident memory of the run, each a power law of the number of neighbour pairs
// fitted in log space. The uncertainty is the fit's scatter: one standard deviation of the log residuals,
// reported as a factor either way.

#include <filesystem>
#include <map>
#include <optional>
#include <string>

namespace vascsim {

/// y = exp(c0) x^c1, times exp(c_tools) for a run with tools, with the scatter of the fit.
struct PowerLaw {
  double c0 = 0.0, c1 = 0.0;
  /// ln of the cost of a run whose scene has tools against one without, at the same size: contact changes the
  /// tangent and refactors the preconditioner (quasi_static's catheter runs against bonded ones: about 3.9x).
  /// 0 when the calibration has no such runs.
  double c_tools = 0.0;
  double log_sigma = 0.0;  ///< standard deviation of ln(measured / fitted)
  int runs = 0;
  double operator()(double x, bool tools = false) const;
  /// exp(log_sigma): the measured values lay within this factor of the fit, either way (one standard
  /// deviation).
  double factor() const;
};

/// One model's calibration.
struct ModelCost {
  std::string step;             ///< what one step is ("load step", "frame", "time step")
  std::string step_length_key;  ///< dynamic models: the key of the model's info() holding the step length, s
  PowerLaw seconds_per_step;    ///< of neighbour pairs
  PowerLaw peak_bytes;          ///< peak resident set of the whole run, of neighbour pairs
  double pairs_min = 0.0, pairs_max = 0.0;  ///< the calibrated range
};

struct CostCalibration {
  std::filesystem::path file;
  std::string measured;    ///< when and under what load
  std::string regenerate;  ///< the command that rewrites the file
  std::map<std::string, ModelCost> models;

  /// Reads a calibration file. Throws InputError naming the file (and key) if it is missing or malformed.
  static CostCalibration read(const std::filesystem::path& file);
  /// data/calibration/cost_model.json of the source tree this binary was built from.
  static std::filesystem::path default_file();
  const ModelCost* find(const std::string& model) const;
};

/// A run's expected cost.
struct CostEstimate {
  std::string step;
  double steps = 0.0;             ///< model steps in the run
  double seconds_per_step = 0.0;  ///< wall time of one, s
  double total_s = 0.0;           ///< steps x seconds_per_step (set-up not included)
  double factor = 1.0;  ///< multiplicative uncertainty of both (one standard deviation of the calibration)
  double peak_bytes = 0.0;  ///< the run's peak resident memory
  double memory_factor = 1.0;
  bool extrapolated = false;  ///< pairs outside the calibrated range
  bool tools = false;         ///< the run's scene has tools (the calibration's c_tools applied)
  int runs = 0;               ///< calibration runs behind the time fit
};

/// The estimate for `model` with `pairs` neighbour pairs and `steps` model steps, for a scene with tools or
/// without; nullopt when the model is not calibrated.
std::optional<CostEstimate> estimate_cost(const CostCalibration& calibration, const std::string& model,
                                          double pairs, double steps, bool tools = false);

/// "12 load steps x 1.9 s = 23 s (within a factor 1.4 either way: ...)", for messages.
std::string describe_cost(const CostEstimate& e);

/// A duration for people: "0.42 s", "3.1 min", "2.2 h".
std::string human_duration(double seconds);

}  // namespace vascsim
