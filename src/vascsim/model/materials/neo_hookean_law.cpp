#include "vascsim/model/materials/neo_hookean_law.hpp"

#include <nlohmann/json.hpp>

#include "vascsim/core/tensor_algebra.hpp"
#include "vascsim/model/materials/parameter_checks.hpp"

namespace vascsim::materials {

StableNeoHookeanEnergy StableNeoHookeanEnergy::from_small_strain(double mu, double lambda_lin) {
  StableNeoHookeanEnergy e;
  e.mu = mu;
  e.lambda_p = lambda_lin + mu;  // see the Lame mapping in the header
  e.alpha = 1.0 + mu / e.lambda_p;
  e.offset = mu * mu / (2.0 * e.lambda_p);
  return e;
}

double StableNeoHookeanEnergy::energy(const Mat3& F) const {
  const double d = F.determinant() - alpha;
  return 0.5 * mu * (F.squaredNorm() - 3.0) + 0.5 * lambda_p * d * d - offset;
}

Mat3 StableNeoHookeanEnergy::first_piola(const Mat3& F) const {
  return mu * F + lambda_p * (F.determinant() - alpha) * cofactor(F);
}

Mat3 StableNeoHookeanEnergy::first_piola_derivative(const Mat3& F, const Mat3& dF) const {
  const Mat3 cof = cofactor(F);
  return mu * dF + lambda_p * (ddot(cof, dF) * cof + (F.determinant() - alpha) * cofactor_derivative(F, dF));
}

NeoHookeanLaw::NeoHookeanLaw(const NeoHookeanParameters& p) : p_(p) {
  const LameConstants l = checked_lame_constants("neo_hookean", p.youngs_modulus_pa, p.poisson_ratio);
  e_ = StableNeoHookeanEnergy::from_small_strain(l.mu, l.lambda);
}

nlohmann::json NeoHookeanLaw::parameters() const {
  return {{"youngs_modulus_pa", p_.youngs_modulus_pa}, {"poisson_ratio", p_.poisson_ratio}};
}

std::string NeoHookeanLaw::reference() const {
  return "Stable neo-Hookean without the log term, psi = mu/2 (I_C - 3) + lambda'/2 (J - 1 - mu/lambda')^2 - "
         "mu^2/(2 lambda'), lambda' = lambda + mu (Smith, de Goes & Kim, ACM TOG 37(2):12, 2018)";
}

}  // namespace vascsim::materials
