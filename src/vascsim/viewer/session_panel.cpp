#include "vascsim/viewer/session_panel.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <sstream>

#include "vascsim/core/error.hpp"
#include "vascsim/model/registry.hpp"
#include "vascsim/viewer/scene_catalog.hpp"

namespace vascsim::viewer {

namespace {

std::string value_text(const JsonField& f) {
  switch (f.kind) {
    case JsonField::Kind::number:
      return fmt::format("{:.17g}", f.value);
    case JsonField::Kind::integer:
      return fmt::format("{}", static_cast<long long>(f.value));
    case JsonField::Kind::boolean:
      return f.value != 0.0 ? "true" : "false";
    case JsonField::Kind::string:
      return f.text;
  }
  return {};
}

}  // namespace

SessionPanel::SessionPanel(LiveSession& session, const Scene& scene, std::string path,
                           std::vector<std::string> overrides, render::HudControls& controls)
    : session_(session),
      controls_(controls),
      path_(std::move(path)),
      overrides_(std::move(overrides)),
      file_scene_(scene) {
  controls_.scene_choices = bundled_scenes(path_);
  controls_.model_choices = model_names_with(&ModelCapabilities::device_driven);
  controls_.scene = path_;
  show(scene);
}

void SessionPanel::show(const Scene& scene) {
  controls_.model = scene.model;
  controls_.youngs_modulus_pa = scene.material.youngs_modulus_pa;
  controls_.poisson_ratio = scene.material.poisson_ratio;
  controls_.model_settings = model_settings_fields(scene, scene.model);
  controls_.has_trajectory = scene.haptics.enabled;
}

std::vector<std::string> SessionPanel::edited_overrides() const {
  std::vector<std::string> out = overrides_;
  if (controls_.model != file_scene_.model) out.push_back("model=" + controls_.model);
  if (controls_.youngs_modulus_pa != file_scene_.material.youngs_modulus_pa)
    out.push_back(fmt::format("material.youngs_modulus_pa={:.17g}", controls_.youngs_modulus_pa));
  if (controls_.poisson_ratio != file_scene_.material.poisson_ratio)
    out.push_back(fmt::format("material.poisson_ratio={:.17g}", controls_.poisson_ratio));
  // A setting goes out when it differs from the file's value for the chosen model (so edits survive
  // rebuilds).
  const std::vector<JsonField> file = model_settings_fields(file_scene_, controls_.model);
  for (const JsonField& f : controls_.model_settings) {
    const auto same =
        std::find_if(file.begin(), file.end(), [&](const JsonField& g) { return g.key == f.key; });
    if (same == file.end() || value_text(*same) != value_text(f)) out.push_back(f.key + "=" + value_text(f));
  }
  std::istringstream more(controls_.overrides);
  for (std::string word; more >> word;) out.push_back(word);
  return out;
}

void SessionPanel::reload(const std::string& path, const std::vector<std::string>& overrides,
                          bool keep_edits) {
  try {
    const Scene scene = load_scene(scene_path(path), overrides);
    if (!keep_edits) {
      file_scene_ = scene;
      path_ = path;
    }
    show(scene);
    session_.post({LiveCommand::Kind::load, scene, {}});
    message_.clear();
  } catch (const InputError& e) {
    message_ = fmt::format("error: {}", e.what());
  }
}

void SessionPanel::handle(const render::HudRequests& r, const KeyRequests& keys) {
  if (r.toggle_pause || keys.toggle_pause) session_.set_paused(!session_.paused());
  controls_.paused = session_.paused();
  if (r.step || keys.step) {
    session_.set_paused(true);
    controls_.paused = true;
    session_.step_once();
  }
  if (r.reset_simulation || keys.reset_scene) session_.post({LiveCommand::Kind::reset, std::nullopt, {}});
  if (r.load_scene) {
    overrides_.clear();  // the command line's overrides belong to its own scene
    controls_.overrides.clear();
    reload(controls_.scene, {}, false);
  }
  if (r.change_model) controls_.model_settings.clear();  // the previous model's block does not apply
  if (r.change_model || r.apply_settings) reload(path_, edited_overrides(), true);
  if (r.toggle_recording) {
    const bool start = !controls_.recording;
    session_.post({start ? LiveCommand::Kind::start_recording : LiveCommand::Kind::stop_recording,
                   std::nullopt, controls_.record_path});
    controls_.recording = start;
  }
  if (r.start_replay) session_.post({LiveCommand::Kind::replay, std::nullopt, controls_.replay_path});
  if (r.play_trajectory) session_.post({LiveCommand::Kind::play_trajectory, std::nullopt, {}});
}

}  // namespace vascsim::viewer
