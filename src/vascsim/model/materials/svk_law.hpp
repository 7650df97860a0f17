#pragma once
// St Venant-Kirchhoff (SVK) law, the sound-mode strain energy of docs/model/07-strain-stress-energy.md:
//
//   E   = 1/2 (F^T F - I)                       Green-Lagrange strain
//   psi = lambda/2 (tr E)^2 + mu tr(E^2)        J/m^3
//   S   = lambda tr(E) I + 2 mu E               2nd Piola-Kirchhoff stress, Pa
//   P   = F S                                   1st Piola-Kirchhoff stress, Pa
//   dP  = dF S + F (lambda tr(dE) I + 2 mu dE),  dE = sym(F^T dF)
//
// lambda = E nu / ((1 + nu)(1 - 2 nu)), mu = E / (2 (1 + nu)) (docs/model/01-notation.md). This is exactly
// PointPrimitiveEnergy's StrainMeasure::GreenHalf term with k_v = 0 (point_primitive_energy.cpp,
// weighted_stress()/stress()); the unit test HyperelasticLawSvk.MatchesPointPrimitiveEnergy checks it.
//
// Parameters: youngs_modulus_pa E > 0 (Pa); poisson_ratio nu in (-1, 0.5).
// Validity: any F. The small-strain response is linear elasticity with (E, nu). Known weaknesses
// (docs/model/17-limitations.md): blind to reflections (psi(QF) = psi(F) for det Q = -1: an inverted node
// costs no energy) and softening in compression below a stretch of 1/sqrt(3). Reference: e.g. Bonet & Wood,
// "Nonlinear Continuum Mechanics for Finite Element Analysis", 2nd ed., Cambridge University Press 2008, Ch.
// 6; Holzapfel, "Nonlinear Solid Mechanics", Wiley 2000, Ch. 6.

#include "vascsim/model/materials/hyperelastic_law.hpp"

namespace vascsim::materials {

struct SvkParameters {
  double youngs_modulus_pa = 0.5e6;
  double poisson_ratio = 0.45;
};

class SvkLaw final : public HyperelasticLaw {
 public:
  /// Throws InputError naming the parameter if E <= 0 or nu is outside (-1, 0.5).
  explicit SvkLaw(const SvkParameters& p);

  const SvkParameters& params() const { return p_; }
  double lame_lambda() const { return lambda_; }

  std::string name() const override { return "svk"; }
  nlohmann::json parameters() const override;
  std::string reference() const override;
  double small_strain_shear_modulus() const override { return mu_; }
  double small_strain_bulk_modulus() const override { return lambda_ + 2.0 * mu_ / 3.0; }

 private:
  double do_energy_density(const Mat3& F, const MaterialFrame* frame) const override;
  Mat3 do_first_piola(const Mat3& F, const MaterialFrame* frame) const override;
  Mat3 do_first_piola_derivative(const Mat3& F, const Mat3& dF, const MaterialFrame* frame) const override;

  SvkParameters p_;
  double lambda_, mu_;
};

}  // namespace vascsim::materials
