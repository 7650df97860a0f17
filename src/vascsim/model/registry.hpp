#pragma once
// Models by name: the scene's top-level key `model` selects one (MODEL.md decision 4).
// Add a model: one file implementing Model, one line in registry.cpp, one name in model_names().

#include <memory>
#include <string>

#include "vascsim/model/explicit_model.hpp"
#include "vascsim/model/paper_literal_model.hpp"
#include "vascsim/model/quasi_static_model.hpp"
#include "vascsim/model/xpbd_model.hpp"

namespace vascsim {

struct ModelSettings {
  ExplicitSettings explicit_settings;
  QuasiStaticSettings quasi_static;
  XpbdSettings xpbd;
  PaperLiteralSettings paper_literal;
};

/// Throws InputError for an unknown name.
std::unique_ptr<Model> make_model(const std::string& name, const Problem& problem, const ModelSettings& settings);

}  // namespace vascsim
