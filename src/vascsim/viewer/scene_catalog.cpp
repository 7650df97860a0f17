#include "vascsim/viewer/scene_catalog.hpp"

#include <algorithm>
#include <filesystem>

#include "vascsim/core/bundled_files.hpp"
#include "vascsim/model/registry.hpp"

namespace vascsim::viewer {

namespace fs = std::filesystem;

std::vector<std::string> bundled_scenes(const std::string& current) {
  std::vector<std::string> out;
  const fs::path source = bundled_root();
  for (const char* dir : {"scenes", "scenes/realtime"}) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(source / dir, ec))
      if (e.is_regular_file() && e.path().extension() == ".json")
        out.push_back((fs::path(dir) / e.path().filename()).string());
  }
  std::sort(out.begin(), out.end());
  if (!current.empty() && std::find(out.begin(), out.end(), current) == out.end())
    out.insert(out.begin(), current);
  return out;
}

std::string scene_path(const std::string& choice) {
  const fs::path p(choice);
  if (p.is_absolute() || fs::exists(p)) return choice;
  const fs::path bundled = bundled_root() / p;
  return fs::exists(bundled) ? bundled.string() : choice;
}

std::vector<JsonField> model_settings_fields(const Scene& scene, const std::string& model) {
  static const nlohmann::json empty = nlohmann::json::object();
  const nlohmann::json& block = scene.resolved.contains(model) ? scene.resolved.at(model) : empty;
  std::vector<JsonField> fields;
  JsonReader reader(block, model, scene.file);
  reader.record_fields(&fields);
  find_model(model).read_settings(reader);
  return fields;
}

}  // namespace vascsim::viewer
