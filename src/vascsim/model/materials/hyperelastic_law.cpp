#include "vascsim/model/materials/hyperelastic_law.hpp"

#include <nlohmann/json.hpp>

namespace vascsim::materials {

nlohmann::json HyperelasticLaw::to_json() const {
  const double mu = small_strain_shear_modulus(), K = small_strain_bulk_modulus();
  // Isotropic linear elasticity: E = 9 K mu / (3K + mu), nu = (3K - 2mu) / (2 (3K + mu)).
  nlohmann::json small;
  small["shear_modulus_pa"] = mu;
  small["bulk_modulus_pa"] = K;
  small["youngs_modulus_pa"] = 9.0 * K * mu / (3.0 * K + mu);
  small["poisson_ratio"] = (3.0 * K - 2.0 * mu) / (2.0 * (3.0 * K + mu));
  return {{"law", name()}, {"parameters", parameters()}, {"small_strain", small}, {"reference", reference()}};
}

}  // namespace vascsim::materials
