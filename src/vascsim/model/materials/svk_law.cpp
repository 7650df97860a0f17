#include "vascsim/model/materials/svk_law.hpp"

#include <nlohmann/json.hpp>

#include "vascsim/model/materials/parameter_checks.hpp"

namespace vascsim::materials {

SvkLaw::SvkLaw(const SvkParameters& p) : p_(p) {
  const LameConstants l = checked_lame_constants("svk", p.youngs_modulus_pa, p.poisson_ratio);
  lambda_ = l.lambda;
  mu_ = l.mu;
}

nlohmann::json SvkLaw::parameters() const {
  return {{"youngs_modulus_pa", p_.youngs_modulus_pa}, {"poisson_ratio", p_.poisson_ratio}};
}

std::string SvkLaw::reference() const {
  return "St Venant-Kirchhoff, psi = lambda/2 (tr E)^2 + mu tr(E^2) (Bonet & Wood 2008, Ch. 6; "
         "docs/model/07-strain-stress-energy.md "
         "section 7)";
}

double SvkLaw::do_energy_density(const Mat3& F, const MaterialFrame* /*frame*/) const {
  const Mat3 E = 0.5 * (F.transpose() * F - Mat3::Identity());
  const double trE = E.trace();
  return 0.5 * lambda_ * trE * trE + mu_ * E.squaredNorm();  // E symmetric: tr(E^2) = E:E
}

Mat3 SvkLaw::do_first_piola(const Mat3& F, const MaterialFrame* /*frame*/) const {
  const Mat3 I = Mat3::Identity();
  const Mat3 E = 0.5 * (F.transpose() * F - I);
  return F * (lambda_ * E.trace() * I + 2.0 * mu_ * E);
}

Mat3 SvkLaw::do_first_piola_derivative(const Mat3& F, const Mat3& dF, const MaterialFrame* /*frame*/) const {
  const Mat3 I = Mat3::Identity();
  const Mat3 E = 0.5 * (F.transpose() * F - I);
  const Mat3 S = lambda_ * E.trace() * I + 2.0 * mu_ * E;
  const Mat3 FtdF = F.transpose() * dF;
  const Mat3 dE = 0.5 * (FtdF + FtdF.transpose());
  return dF * S + F * (lambda_ * dE.trace() * I + 2.0 * mu_ * dE);
}

}  // namespace vascsim::materials
