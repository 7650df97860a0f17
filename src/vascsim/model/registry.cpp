#include "vascsim/model/registry.hpp"

#include "vascsim/core/error.hpp"

namespace vascsim {

std::unique_ptr<Model> make_model(const std::string& name, const Problem& problem, const ModelSettings& settings) {
  if (name == "explicit") return std::make_unique<ExplicitModel>(problem, settings.explicit_settings);
  if (name == "quasi_static") return std::make_unique<QuasiStaticModel>(problem, settings.quasi_static);
  if (name == "xpbd") return std::make_unique<XpbdModel>(problem, settings.xpbd);
  if (name == "paper_literal") return std::make_unique<PaperLiteralModel>(problem, settings.paper_literal);
  throw InputError("unknown model '" + name + "'; allowed: quasi_static, explicit, xpbd, paper_literal");
}

}  // namespace vascsim
