#pragma once
// What the panel offers to choose from: the bundled scenes (scenes/*.json and scenes/realtime/*.json of the
// bundled files (core/bundled_files.hpp), plus the scene the viewer was started with) and each model's
// settings as its own reader takes them (the models a device can drive come from the registry:
// model_names_with(device_driven)).

#include <string>
#include <vector>

#include "vascsim/core/json_reader.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim::viewer {

/// Scene files as "scenes/NAME.json" and "scenes/realtime/NAME.json" (sorted), `current` (as given) first if
/// it is not among them.
std::vector<std::string> bundled_scenes(const std::string& current);

/// The file of a choice: as given if it exists (or is absolute), else among the bundled files.
std::string scene_path(const std::string& choice);

/// The settings block of `model` as its registry reader takes it for `scene` (the file's values or the
/// defaults), each with its allowed range: what the panel lets the user edit.
std::vector<JsonField> model_settings_fields(const Scene& scene, const std::string& model);

}  // namespace vascsim::viewer
