#include "vascsim/experiments/run_assessment.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <cmath>

#include "vascsim/core/error.hpp"
#include "vascsim/model/discretization.hpp"
#include "vascsim/model/registry.hpp"

namespace vascsim {

double headless_model_steps(const Scene& scene, Simulation& sim, const ModelCost* cost) {
  const ModelEntry& entry = find_model(scene.model);
  Model& model = sim.model();
  if (!entry.capabilities.dynamic || !entry.schedule || cost == nullptr || cost->step_length_key.empty())
    return model.num_steps();
  const nlohmann::json info = model.info();
  const auto step = info.find(cost->step_length_key);
  if (step == info.end() || !step->is_number() || !(step->get<double>() > 0.0)) return model.num_steps();
  return std::ceil(entry.schedule(scene.own_model_settings()).duration_s / step->get<double>() - 1e-9);
}

std::optional<CostEstimate> estimate_run_cost(const CostCalibration& calibration, const Scene& scene,
                                              Simulation& sim, double steps) {
  return estimate_cost(calibration, scene.model, static_cast<double>(sim.discretization().pairs().col.size()),
                       steps, !scene.obstacles.empty());
}

std::vector<std::string> model_accuracy_warnings(const ForceAccuracyTable& table, const Scene& scene,
                                                 Simulation& sim) {
  std::vector<std::string> warnings = scene.warnings;
  for (const SubstepStiffnessRule& rule : table.substep_rules) {
    if (rule.model != scene.model) continue;
    const nlohmann::json info = sim.model().info();
    const auto h = info.find(rule.substep_key);
    if (h == info.end() || !h->is_number()) continue;
    const double spacing = sim.discretization().mean_spacing();
    const double q = substep_stiffness_ratio(h->get<double>(), scene.material, spacing);
    if (q <= rule.warn_above) continue;
    warnings.push_back(
        fmt::format("{} is far off at these settings: its per-substep stiffness ratio (h c_p / spacing)^2 is "
                    "{:.3g} (substep {:.3g} "
                    "s, spacing {:.3g} m; above {:.3g} its forces fall short): measured {}. For forces use "
                    "quasi_static or "
                    "implicit, or shrink the substep ({}.substeps)",
                    rule.model, q, h->get<double>(), spacing, rule.warn_above, rule.measured, rule.model));
  }
  if (const std::string w = linear_fit_layers_warning(scene, sim); !w.empty()) warnings.push_back(w);
  return warnings;
}

std::string linear_fit_layers_warning(const Scene& scene, const Simulation& sim) {
  const Discretization& disc = sim.discretization();
  const auto& wall = sim.body().wall;
  if (disc.basis() != GradientBasis::Linear ||
      scene.discretization.support != DiscretizationOptions::Support::Wall ||
      scene.discretization.wall_reach != DiscretizationOptions::WallReach::Layers || !wall ||
      !(wall->layer_spacing_m > 0.0))
    return "";
  const int layers = static_cast<int>(std::lround(wall->thickness_m / wall->layer_spacing_m)) + 1;
  if (layers < 4) return "";
  return fmt::format(
      "the linear fit with supports of a node's own reach through the wall (discretization.basis 'linear', "
      "wall_reach 'layers') is stiff on a wall of {} node layers: measured +8 % (bonded) to +24 % (catheter) "
      "with "
      "four layers on the vein, against -2.5..+2.7 % with three (docs/validation.md, 'Layers through the "
      "wall'). Use "
      "geometry.min_layers=3 with it, as the real-time scenes do, or discretization.basis=quadratic",
      layers);
}

namespace {

template <class T>
const T* read_once(const std::filesystem::path& file) {
  static const std::optional<T> value = [&]() -> std::optional<T> {
    try {
      return T::read(file);
    } catch (const InputError& e) {
      spdlog::debug("{}", e.what());
      return std::nullopt;
    }
  }();
  return value ? &*value : nullptr;
}

}  // namespace

const CostCalibration* bundled_cost_calibration() {
  return read_once<CostCalibration>(CostCalibration::default_file());
}

const ForceAccuracyTable* bundled_force_accuracy() {
  return read_once<ForceAccuracyTable>(ForceAccuracyTable::default_file());
}

}  // namespace vascsim
