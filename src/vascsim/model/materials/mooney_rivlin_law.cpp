#include "vascsim/model/materials/mooney_rivlin_law.hpp"

#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

#include "vascsim/core/tensor_algebra.hpp"
#include "vascsim/model/materials/parameter_checks.hpp"

namespace vascsim::materials {

namespace {
const Mat3 kNaN = Mat3::Constant(std::numeric_limits<double>::quiet_NaN());
}  // namespace

MooneyRivlinLaw::MooneyRivlinLaw(const MooneyRivlinParameters& p) : p_(p) {
  require_non_negative("mooney_rivlin", "c10_pa", p.c10_pa);
  require_non_negative("mooney_rivlin", "c01_pa", p.c01_pa);
  require_positive("mooney_rivlin", "c10_pa + c01_pa", p.c10_pa + p.c01_pa);
  require_positive("mooney_rivlin", "bulk_modulus_pa", p.bulk_modulus_pa);
}

nlohmann::json MooneyRivlinLaw::parameters() const {
  return {{"c10_pa", p_.c10_pa}, {"c01_pa", p_.c01_pa}, {"bulk_modulus_pa", p_.bulk_modulus_pa}};
}

std::string MooneyRivlinLaw::reference() const {
  return "Compressible Mooney-Rivlin with isochoric invariants, psi = C10 (Ib1 - 3) + C01 (Ib2 - 3) + "
         "kappa/2 "
         "(J - 1)^2 (Holzapfel, Nonlinear Solid Mechanics, 2000, Ch. 6)";
}

double MooneyRivlinLaw::do_energy_density(const Mat3& F, const MaterialFrame* /*frame*/) const {
  const double J = F.determinant();
  if (!(J > 0.0)) return std::numeric_limits<double>::infinity();
  const Mat3 C = F.transpose() * F;
  const double I1 = C.trace();
  const double I2 = 0.5 * (I1 * I1 - C.squaredNorm());  // C symmetric: tr(C^2) = C:C
  const double a = std::pow(J, -2.0 / 3.0);
  return p_.c10_pa * (a * I1 - 3.0) + p_.c01_pa * (a * a * I2 - 3.0) +
         0.5 * p_.bulk_modulus_pa * (J - 1.0) * (J - 1.0);
}

Mat3 MooneyRivlinLaw::do_first_piola(const Mat3& F, const MaterialFrame* /*frame*/) const {
  const Mat3 cof = cofactor(F);
  const double J = F.determinant();
  if (!(J > 0.0)) return kNaN;
  const Mat3 G = cof / J;  // F^{-T}
  const Mat3 C = F.transpose() * F;
  const double I1 = C.trace();
  const double I2 = 0.5 * (I1 * I1 - C.squaredNorm());
  const double a = std::pow(J, -2.0 / 3.0), b = a * a;
  return 2.0 * p_.c10_pa * a * (F - I1 / 3.0 * G) +
         2.0 * p_.c01_pa * b * (I1 * F - F * C - 2.0 / 3.0 * I2 * G) + p_.bulk_modulus_pa * (J - 1.0) * cof;
}

Mat3 MooneyRivlinLaw::do_first_piola_derivative(const Mat3& F, const Mat3& dF,
                                                const MaterialFrame* /*frame*/) const {
  const Mat3 cof = cofactor(F);
  const double J = F.determinant();
  if (!(J > 0.0)) return kNaN;
  const Mat3 G = cof / J;
  const Mat3 C = F.transpose() * F;
  const double I1 = C.trace();
  const double I2 = 0.5 * (I1 * I1 - C.squaredNorm());
  const double a = std::pow(J, -2.0 / 3.0), b = a * a;
  const double c10 = p_.c10_pa, c01 = p_.c01_pa, kappa = p_.bulk_modulus_pa;

  const double t = ddot(G, dF);  // dJ / J
  const Mat3 dG = -G * dF.transpose() * G;
  const double da = -2.0 / 3.0 * a * t, db = -4.0 / 3.0 * b * t;
  const double dI1 = 2.0 * ddot(F, dF);
  const Mat3 dI2dF = I1 * F - F * C;  // 1/2 dI2/dF
  const double dI2 = 2.0 * ddot(dI2dF, dF);
  const Mat3 dC = dF.transpose() * F + F.transpose() * dF;

  const Mat3 d1 = 2.0 * c10 * (da * (F - I1 / 3.0 * G) + a * (dF - dI1 / 3.0 * G - I1 / 3.0 * dG));
  const Mat3 d2 = 2.0 * c01 *
                  (db * (dI2dF - 2.0 / 3.0 * I2 * G) +
                   b * (dI1 * F + I1 * dF - dF * C - F * dC - 2.0 / 3.0 * dI2 * G - 2.0 / 3.0 * I2 * dG));
  // d[kappa (J^2 - J) G] = kappa [(2J - 1) dJ G + (J^2 - J) dG], dJ = J t.
  const Mat3 d3 = kappa * ((2.0 * J - 1.0) * J * t * G + (J * J - J) * dG);
  return d1 + d2 + d3;
}

}  // namespace vascsim::materials
