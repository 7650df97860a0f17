#pragma once
// Parsing of the JSON files vascsim reads (scenes, trajectories, --set values): comments allowed, nesting
// bounded, and every problem one InputError line in vascsim's words naming the file.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace vascsim {

/// Deepest nesting of arrays and objects accepted (a scene nests about 5 levels). Deeper documents are
/// rejected while parsing: copying or printing one recurses once per level and would overflow the stack.
inline constexpr int kMaxJsonDepth = 64;

/// Parses `text` read from `file` (the name in messages). Throws InputError:
/// "<file>: not valid JSON: line L, column C: <what is wrong>".
nlohmann::json parse_json_text(const std::string& text, const std::string& file);

/// Parses `text` if it is JSON within kMaxJsonDepth, else nullopt (a --set value that is a bare word).
std::optional<nlohmann::json> try_parse_json(const std::string& text);

/// Reads and parses a regular file of at most 256 MiB. Messages name it as `noun` ("the scene file") and end
/// with `expected` (e.g. "expected a JSON trajectory {\"samples\": [...]}").
nlohmann::json read_json_file(const std::filesystem::path& file, const std::string& noun,
                              const std::string& expected);

}  // namespace vascsim
