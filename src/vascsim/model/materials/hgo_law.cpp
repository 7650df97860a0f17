#include "vascsim/model/materials/hgo_law.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "vascsim/model/materials/parameter_checks.hpp"

namespace vascsim::materials {

namespace {
const MaterialFrame& require_frame(const MaterialFrame* frame) {
  // A missing frame is a bug in the caller (needs_frame() is true), not a user input error.
  if (!frame) throw std::logic_error("hyperelastic law 'hgo' evaluated without a MaterialFrame");
  return *frame;
}
}  // namespace

HgoParameters hgo2000_carotid_media(double bulk_modulus_pa) {
  return {3.0e3, bulk_modulus_pa, 2.3632e3, 0.8393, 29.0};
}

HgoParameters hgo2000_carotid_adventitia(double bulk_modulus_pa) {
  return {0.3e3, bulk_modulus_pa, 0.5620e3, 0.7112, 62.0};
}

HgoLaw::HgoLaw(const HgoParameters& p) : p_(p) {
  require_positive("hgo", "shear_modulus_pa", p.shear_modulus_pa);
  require_positive("hgo", "bulk_modulus_pa", p.bulk_modulus_pa);
  require_non_negative("hgo", "k1_pa", p.k1_pa);
  require_non_negative("hgo", "k2", p.k2);
  require_closed_range("hgo", "fibre_angle_deg", p.fibre_angle_deg, 0.0, 90.0);
  const double mu = p.shear_modulus_pa;
  ground_ = StableNeoHookeanEnergy::from_small_strain(
      mu, p.bulk_modulus_pa - 2.0 * mu / 3.0);  // lambda = K - 2mu/3
  const double beta = p.fibre_angle_deg * std::numbers::pi / 180.0;
  cos_beta_ = std::cos(beta);
  sin_beta_ = std::sin(beta);
}

nlohmann::json HgoLaw::parameters() const {
  return {{"shear_modulus_pa", p_.shear_modulus_pa},
          {"bulk_modulus_pa", p_.bulk_modulus_pa},
          {"k1_pa", p_.k1_pa},
          {"k2", p_.k2},
          {"fibre_angle_deg", p_.fibre_angle_deg}};
}

std::string HgoLaw::reference() const {
  return "Holzapfel-Gasser-Ogden, psi = stable neo-Hookean ground + sum_{i=4,6} k1/(2k2) [exp(k2 (I_i - "
         "1)^2) - 1] "
         "(I_i > 1) with full invariants I_i = a_i.C a_i (Holzapfel, Gasser & Ogden, J. Elasticity 61:1-48, "
         "2000; "
         "Nolan et al., J. Mech. Behav. Biomed. Mater. 39:48-60, 2014)";
}

// I - 1 is evaluated as |F a|^2 - |a|^2 (|a|^2 = 1 to rounding), which is exactly 0 at F = I: the rest
// state is on the slack side of the kink whatever the rounding of cos(beta), sin(beta) (see the header).
double HgoLaw::fibre_energy(const Mat3& F, const Vec3& a) const {
  const double x = (F * a).squaredNorm() - a.squaredNorm();
  if (!(x > 0.0)) return 0.0;
  const double x2 = x * x;
  // k1/(2k2) (exp(k2 x^2) - 1), with expm1 for accuracy at small k2 x^2 and the k2 = 0 limit k1 x^2 / 2.
  return p_.k2 > 0.0 ? 0.5 * p_.k1_pa * std::expm1(p_.k2 * x2) / p_.k2 : 0.5 * p_.k1_pa * x2;
}

Mat3 HgoLaw::fibre_piola(const Mat3& F, const Vec3& a) const {
  const Vec3 f = F * a;
  const double x = f.squaredNorm() - a.squaredNorm();
  if (!(x > 0.0)) return Mat3::Zero();
  const double dpsi = p_.k1_pa * x * std::exp(p_.k2 * x * x);
  return 2.0 * dpsi * f * a.transpose();
}

Mat3 HgoLaw::fibre_piola_derivative(const Mat3& F, const Mat3& dF, const Vec3& a) const {
  const Vec3 f = F * a;
  const double x = f.squaredNorm() - a.squaredNorm();
  if (!(x > 0.0)) return Mat3::Zero();
  const double e = std::exp(p_.k2 * x * x);
  const double dpsi = p_.k1_pa * x * e;
  const double d2psi = p_.k1_pa * e * (1.0 + 2.0 * p_.k2 * x * x);
  const Vec3 df = dF * a;
  const double dI = 2.0 * f.dot(df);
  return 2.0 * (d2psi * dI * f + dpsi * df) * a.transpose();
}

double HgoLaw::do_energy_density(const Mat3& F, const MaterialFrame* frame) const {
  const MaterialFrame& fr = require_frame(frame);
  return ground_.energy(F) + fibre_energy(F, fibre4(fr)) + fibre_energy(F, fibre6(fr));
}

Mat3 HgoLaw::do_first_piola(const Mat3& F, const MaterialFrame* frame) const {
  const MaterialFrame& fr = require_frame(frame);
  return ground_.first_piola(F) + fibre_piola(F, fibre4(fr)) + fibre_piola(F, fibre6(fr));
}

Mat3 HgoLaw::do_first_piola_derivative(const Mat3& F, const Mat3& dF, const MaterialFrame* frame) const {
  const MaterialFrame& fr = require_frame(frame);
  return ground_.first_piola_derivative(F, dF) + fibre_piola_derivative(F, dF, fibre4(fr)) +
         fibre_piola_derivative(F, dF, fibre6(fr));
}

}  // namespace vascsim::materials
