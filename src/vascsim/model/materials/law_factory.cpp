#include "vascsim/model/materials/law_factory.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <initializer_list>
#include <nlohmann/json.hpp>

#include "vascsim/core/error.hpp"
#include "vascsim/model/materials/hgo_law.hpp"
#include "vascsim/model/materials/mooney_rivlin_law.hpp"
#include "vascsim/model/materials/neo_hookean_law.hpp"
#include "vascsim/model/materials/svk_law.hpp"

namespace vascsim::materials {

namespace {

// Checks the key set of `params` against `keys` (all required, no others) and reads them as numbers.
class ParameterReader {
 public:
  ParameterReader(std::string_view law, const nlohmann::json& params, std::initializer_list<const char*> keys)
      : law_(law), params_(params) {
    if (!params.is_object())
      throw InputError(
          fmt::format("hyperelastic law '{}': parameters must be a JSON object, got {}", law, params.dump()));
    for (const auto& item : params.items()) {
      if (std::none_of(keys.begin(), keys.end(), [&](const char* k) { return item.key() == k; }))
        throw InputError(fmt::format("hyperelastic law '{}': unknown parameter '{}' (expected: {})", law,
                                     item.key(), fmt::join(keys, ", ")));
    }
  }

  double number(const char* key) const {
    const auto it = params_.find(key);
    if (it == params_.end())
      throw InputError(fmt::format("hyperelastic law '{}': missing parameter '{}'", law_, key));
    if (!it->is_number())
      throw InputError(fmt::format("hyperelastic law '{}': parameter '{}' must be a number, got {}", law_,
                                   key, it->dump()));
    return it->get<double>();
  }

 private:
  std::string_view law_;
  const nlohmann::json& params_;
};

}  // namespace

const std::vector<std::string>& hyperelastic_law_names() {
  static const std::vector<std::string> names{"svk", "neo_hookean", "mooney_rivlin", "hgo"};
  return names;
}

std::unique_ptr<HyperelasticLaw> make_hyperelastic_law(std::string_view name,
                                                       const nlohmann::json& parameters) {
  if (name == "svk") {
    const ParameterReader r(name, parameters, {"youngs_modulus_pa", "poisson_ratio"});
    return std::make_unique<SvkLaw>(SvkParameters{r.number("youngs_modulus_pa"), r.number("poisson_ratio")});
  }
  if (name == "neo_hookean") {
    const ParameterReader r(name, parameters, {"youngs_modulus_pa", "poisson_ratio"});
    return std::make_unique<NeoHookeanLaw>(
        NeoHookeanParameters{r.number("youngs_modulus_pa"), r.number("poisson_ratio")});
  }
  if (name == "mooney_rivlin") {
    const ParameterReader r(name, parameters, {"c10_pa", "c01_pa", "bulk_modulus_pa"});
    return std::make_unique<MooneyRivlinLaw>(
        MooneyRivlinParameters{r.number("c10_pa"), r.number("c01_pa"), r.number("bulk_modulus_pa")});
  }
  if (name == "hgo") {
    const ParameterReader r(name, parameters,
                            {"shear_modulus_pa", "bulk_modulus_pa", "k1_pa", "k2", "fibre_angle_deg"});
    return std::make_unique<HgoLaw>(HgoParameters{r.number("shear_modulus_pa"), r.number("bulk_modulus_pa"),
                                                  r.number("k1_pa"), r.number("k2"),
                                                  r.number("fibre_angle_deg")});
  }
  throw InputError(fmt::format("unknown hyperelastic law '{}' (expected one of: {})", name,
                               fmt::join(hyperelastic_law_names(), ", ")));
}

}  // namespace vascsim::materials
