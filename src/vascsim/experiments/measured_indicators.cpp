#include "vascsim/experiments/measured_indicators.hpp"

#include <fmt/format.h>
#include <map>

namespace vascsim {

nlohmann::json ahp_measurements(const std::vector<TimingPoint>& points, const nlohmann::json& rms_error,
                                const std::string& source) {
  std::vector<std::string> order;
  std::map<std::string, nlohmann::json> models;
  auto entry = [&](const std::string& id) -> nlohmann::json& {
    if (!models.count(id)) {
      order.push_back(id);
      models[id] = {{"id", id}};
    }
    return models[id];
  };
  std::map<std::string, int> largest;
  for (const auto& p : points)
    if (p.nodes > largest[p.model]) largest[p.model] = p.nodes;
  for (const auto& p : points) {
    if (p.nodes != largest[p.model]) continue;
    nlohmann::json& m = entry(p.model);
    m["nodes"] = p.nodes;
    m["update_time_ms"] = p.simulation_median_ms;
    m["visual_refresh_rate_hz"] = p.frames_per_s;
  }
  std::string reference;
  if (rms_error.is_object() && rms_error.contains("models")) {
    reference = rms_error.value("reference", "");
    for (const auto& r : rms_error["models"]) {
      const std::string id = r.at("model").get<std::string>();
      if (id == reference) continue;
      entry(id)["force_rms_error_percent"] = r.at("rms_percent").get<double>();
    }
  }
  nlohmann::json list = nlohmann::json::array();
  for (const auto& id : order) list.push_back(models[id]);
  return {
      {"source", source},
      {"description", fmt::format("update time and frames per second at each model's largest timed node count"
                                  "{}",
                                  reference.empty() ? "" : "; force RMS error against " + reference)},
      {"models", list}};
}

}  // namespace vascsim
