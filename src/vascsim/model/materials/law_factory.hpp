#pragma once
// Construction of a hyperelastic law from a name and a JSON parameter object (scene files, summary.json
// round trips). Laws can also be built directly from their parameter structs (svk_law.hpp, ...); both
// ways validate the parameters the same way.
//
//   name            parameters (all required, SI units)
//   "svk"           youngs_modulus_pa, poisson_ratio
//   "neo_hookean"   youngs_modulus_pa, poisson_ratio
//   "mooney_rivlin" c10_pa, c01_pa, bulk_modulus_pa
//   "hgo"           shear_modulus_pa, bulk_modulus_pa, k1_pa, k2, fibre_angle_deg
//
// make_hyperelastic_law(law.name(), law.parameters()) rebuilds an identical law.

#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "vascsim/model/materials/hyperelastic_law.hpp"

namespace vascsim::materials {

/// The names make_hyperelastic_law accepts.
const std::vector<std::string>& hyperelastic_law_names();

/// Throws InputError, naming the law and the key, for an unknown law name, a parameter object that is not
/// a JSON object, a missing or non-numeric parameter, an unknown key, or a value out of range.
std::unique_ptr<HyperelasticLaw> make_hyperelastic_law(std::string_view name,
                                                       const nlohmann::json& parameters);

}  // namespace vascsim::materials
