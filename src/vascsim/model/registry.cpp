#include "vascsim/model/registry.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "vascsim/core/error.hpp"
#include "vascsim/model/explicit_model.hpp"
#include "vascsim/model/fem_quasi_newton_model.hpp"
#include "vascsim/model/filling_model.hpp"
#include "vascsim/model/implicit_model.hpp"
#include "vascsim/model/mass_spring_model.hpp"
#include "vascsim/model/paper_literal_model.hpp"
#include "vascsim/model/pbd_viscoelastic_model.hpp"
#include "vascsim/model/quasi_static_model.hpp"
#include "vascsim/model/tensor_mass_model.hpp"
#include "vascsim/model/xpbd_model.hpp"

namespace vascsim {

const std::vector<ModelEntry>& model_registry() {
  static const std::vector<ModelEntry> entries = {
      quasi_static_model_entry(),     explicit_model_entry(),    xpbd_model_entry(),
      paper_literal_model_entry(),    implicit_model_entry(),    mass_spring_model_entry(),
      fem_quasi_newton_model_entry(), tensor_mass_model_entry(), filling_model_entry(),
      pbd_viscoelastic_model_entry(),
  };
  return entries;
}

std::vector<std::string> model_names() {
  std::vector<std::string> names;
  for (const ModelEntry& e : model_registry()) names.push_back(e.name);
  return names;
}

std::string default_model_name(bool device_driven) {
  return device_driven ? "implicit" : "quasi_static";
}

std::vector<std::string> model_names_with(bool ModelCapabilities::*capability) {
  std::vector<std::string> names;
  for (const ModelEntry& e : model_registry())
    if (e.capabilities.*capability) names.push_back(e.name);
  return names;
}

const ModelEntry& find_model(const std::string& name) {
  for (const ModelEntry& e : model_registry())
    if (e.name == name) return e;
  throw InputError(fmt::format("unknown model '{}'; allowed: {}", name, fmt::join(model_names(), ", ")));
}

std::unique_ptr<Model> make_model(const std::string& name, const Problem& problem, const std::any& settings) {
  return find_model(name).make(problem, settings);
}

}  // namespace vascsim
