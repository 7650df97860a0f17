#pragma once
// The scene parser's input errors, for tests that check a key is refused with a message that names it.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "vascsim/core/error.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim::test {

/// The message of the InputError that parse_scene(doc) throws; records a test failure (and returns "") when
/// it parses.
inline std::string scene_error(const nlohmann::json& doc, const std::string& file = "scene.json") {
  try {
    parse_scene(doc, file);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << file << " parsed; an input error was expected";
  return {};
}

}  // namespace vascsim::test
