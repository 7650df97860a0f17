#include "vascsim/experiments/cost_model.hpp"

#include <fmt/format.h>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "vascsim/core/bundled_files.hpp"
#include "vascsim/core/error.hpp"

namespace vascsim {

namespace {

PowerLaw read_power_law(const nlohmann::json& j) {
  PowerLaw p;
  p.c0 = j.at("c0").get<double>();
  p.c1 = j.at("c1").get<double>();
  p.c_tools = j.value("c_tools", 0.0);
  p.log_sigma = j.at("log_sigma").get<double>();
  p.runs = j.at("runs").get<int>();
  return p;
}

}  // namespace

double PowerLaw::operator()(double x, bool tools) const {
  return std::exp(c0 + c1 * std::log(x) + (tools ? c_tools : 0.0));
}

double PowerLaw::factor() const {
  return std::exp(log_sigma);
}

CostCalibration CostCalibration::read(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw InputError(fmt::format("{}: cannot read the cost calibration", file.string()));
  CostCalibration c;
  c.file = file;
  try {
    const nlohmann::json doc = nlohmann::json::parse(in);
    c.measured = doc.at("measured").get<std::string>();
    c.regenerate = doc.at("regenerate").get<std::string>();
    for (const auto& [name, m] : doc.at("models").items()) {
      ModelCost cost;
      cost.step = m.at("step").get<std::string>();
      cost.step_length_key = m.value("step_length_key", "");
      cost.seconds_per_step = read_power_law(m.at("seconds_per_step"));
      cost.peak_bytes = read_power_law(m.at("peak_bytes"));
      cost.pairs_min = m.at("pairs_range").at(0).get<double>();
      cost.pairs_max = m.at("pairs_range").at(1).get<double>();
      c.models[name] = cost;
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(
        fmt::format("{}: not a cost calibration ({}); regenerate it with "
                    "scripts/calibrate_cost_model.py",
                    file.string(), e.what()));
  }
  return c;
}

std::filesystem::path CostCalibration::default_file() {
  return bundled_file("data/calibration/cost_model.json");
}

const ModelCost* CostCalibration::find(const std::string& model) const {
  const auto it = models.find(model);
  return it == models.end() ? nullptr : &it->second;
}

std::optional<CostEstimate> estimate_cost(const CostCalibration& calibration, const std::string& model,
                                          double pairs, double steps, bool tools) {
  const ModelCost* m = calibration.find(model);
  if (m == nullptr || !(pairs > 0.0)) return std::nullopt;
  CostEstimate e;
  e.step = m->step;
  e.steps = steps;
  e.tools = tools;
  e.seconds_per_step = m->seconds_per_step(pairs, tools);
  e.total_s = steps * e.seconds_per_step;
  e.factor = m->seconds_per_step.factor();
  e.peak_bytes = m->peak_bytes(pairs);
  e.memory_factor = m->peak_bytes.factor();
  // Up to a factor 2 past the calibrated sizes still counts as calibrated (the power law is smooth there).
  e.extrapolated = pairs < 0.5 * m->pairs_min || pairs > 2.0 * m->pairs_max;
  e.runs = m->seconds_per_step.runs;
  return e;
}

std::string human_duration(double seconds) {
  if (seconds < 1.0) return fmt::format("{:.3g} ms", 1e3 * seconds);
  if (seconds < 120.0) return fmt::format("{:.3g} s", seconds);
  if (seconds < 7200.0) return fmt::format("{:.3g} min", seconds / 60.0);
  return fmt::format("{:.3g} h", seconds / 3600.0);
}

std::string describe_cost(const CostEstimate& e) {
  return fmt::format(
      "{:.4g} {}s x {} = {} (within a factor {:.2g} either way: 1 sigma of {} calibration runs{})", e.steps,
      e.step, human_duration(e.seconds_per_step), human_duration(e.total_s), e.factor, e.runs,
      e.extrapolated ? "; this size is outside the calibrated ones" : "");
}

}  // namespace vascsim
