#pragma once
// `vascsim validate mls`: docs/validation.md T11 (MLS reproduction) and T15 (conditioning guards) on the
// render surface of each scene's body, for the per-vessel table of docs/validation.md.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace vascsim {

/// For every scene file (with --set style overrides applied to each): builds the body, the MLS map with
/// the scene's mapping options and measures T11; then rebuilds it with a deliberately small support
/// (factor `tight_factor`) to exercise T15: the guard must grow r (reported) or fail naming a vertex
/// (reported), never accept an ill-conditioned vertex. Returns one JSON object per scene.
nlohmann::json validate_mls(const std::vector<std::string>& scene_files,
                            const std::vector<std::string>& overrides, double tight_factor);

/// A Markdown table of validate_mls's result.
std::string mls_validation_table(const nlohmann::json& rows);

}  // namespace vascsim
