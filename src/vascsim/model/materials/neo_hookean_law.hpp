#pragma once
// Stable neo-Hookean law of Smith, de Goes & Kim, "Stable Neo-Hookean Flesh Simulation", ACM Trans.
// Graph. 37(2):12, 2018, in the form without the log term:
//
//   psi = mu/2 (I_C - 3) + lambda'/2 (J - alpha)^2 - mu^2 / (2 lambda')             J/m^3
//   I_C = tr(F^T F),  J = det F,  alpha = 1 + mu/lambda'
//   P   = mu F + lambda' (J - alpha) cof(F),                 cof(F) = dJ/dF = J F^{-T}
//   dP  = mu dF + lambda' [ (cof(F):dF) cof(F) + (J - alpha) dcof(F)[dF] ]
//
// - alpha = 1 + mu/lambda' makes F = I stress free (rest stability: P(I) = mu I + lambda'(1 - alpha) I = 0).
// - The constant -mu^2/(2 lambda') makes psi(I) = 0 (it does not change P).
// - Which variant: the paper's final energy adds -mu/2 log(I_C + 1) (with alpha = 1 + 3mu/(4lambda')).
//   We leave it out: (1) rest stability and the inversion behaviour below hold without it; (2) psi stays a
//   polynomial in F, so P and the exact dP are short and cheap; (3) it is the energy of vascsim's XPBD tet
//   constraint pair (constraints/tet_neo_hookean_constraint.hpp, Macklin & Mueller 2021; xpbd_model.cpp
//   passes lambda' = lambda + mu to it, as here), so both models use the same material.
//   For reference, with the log term the same expansion as below gives mu_lin = 3mu/4 and
//   lambda_lin = lambda' - 5mu/8, i.e. mu = 4/3 mu_lin and lambda' = lambda_lin + 5/6 mu_lin.
//
// Lame mapping (derived here). With F = I + H, eps = sym(H):
//   I_C = 3 + 2 tr H + H:H,   J = 1 + tr H + 1/2 [(tr H)^2 - H:H^T] + O(|H|^3),
//   lambda'/2 (J - alpha)^2 - mu^2/(2 lambda') = -mu (J - 1) + lambda'/2 (J - 1)^2      (exact),
//   psi = mu/2 (H:H + H:H^T) + (lambda' - mu)/2 (tr H)^2 + O(|H|^3)
//       = mu eps:eps + (lambda' - mu)/2 (tr eps)^2 + O(|H|^3)          (H:H + H:H^T = 2 eps:eps).
// Linear elasticity is psi_lin = mu eps:eps + lambda/2 (tr eps)^2, so the law matches (E, nu) at small
// strain with the same shear modulus mu and
//   lambda' = lambda + mu = E / (2 (1 + nu)(1 - 2 nu))     (> 0 for every admissible nu),
// where lambda = E nu / ((1 + nu)(1 - 2 nu)) and mu = E / (2 (1 + nu)) (docs/model/01-notation.md).
//
// Inversion (det F <= 0): psi is a polynomial, so it is finite for every F, and P is continuous. The
// volumetric term pulls J towards alpha > 0: for F = diag(1, 1, s),
//   d psi / ds = mu s + lambda' (s - alpha) = (lambda' + mu)(s - 1) < 0 for every s < 1,
// so an inverted node (s < 0) feels a restoring force and the energy decreases monotonically all the way
// back to F = I (test HyperelasticLawNeoHookean.InvertedHasFiniteEnergyAndRestoringForce).
//
// Parameters: youngs_modulus_pa E > 0 (Pa); poisson_ratio nu in (-1, 0.5). Valid for any F.

#include "vascsim/model/materials/hyperelastic_law.hpp"

namespace vascsim::materials {

/// The stable neo-Hookean energy as a plain value (no virtual calls), shared by NeoHookeanLaw and the
/// ground matrix of HgoLaw.
struct StableNeoHookeanEnergy {
  double mu = 0.0;        ///< shear modulus, Pa
  double lambda_p = 0.0;  ///< lambda' = lambda_lin + mu, Pa
  double alpha = 1.0;     ///< 1 + mu/lambda'
  double offset = 0.0;    ///< mu^2 / (2 lambda'), J/m^3

  /// From the small-strain shear modulus mu and Lame lambda of the linear elasticity to match (Pa);
  /// requires mu > 0 and lambda + mu > 0 (checked by the callers).
  static StableNeoHookeanEnergy from_small_strain(double mu, double lambda_lin);

  double energy(const Mat3& F) const;
  Mat3 first_piola(const Mat3& F) const;
  Mat3 first_piola_derivative(const Mat3& F, const Mat3& dF) const;
};

struct NeoHookeanParameters {
  double youngs_modulus_pa = 0.5e6;
  double poisson_ratio = 0.45;
};

class NeoHookeanLaw final : public HyperelasticLaw {
 public:
  /// Throws InputError naming the parameter if E <= 0 or nu is outside (-1, 0.5).
  explicit NeoHookeanLaw(const NeoHookeanParameters& p);

  const NeoHookeanParameters& params() const { return p_; }
  const StableNeoHookeanEnergy& energy() const { return e_; }

  std::string name() const override { return "neo_hookean"; }
  nlohmann::json parameters() const override;
  std::string reference() const override;
  double small_strain_shear_modulus() const override { return e_.mu; }
  double small_strain_bulk_modulus() const override { return e_.lambda_p - e_.mu / 3.0; }  // lambda + 2mu/3

 private:
  double do_energy_density(const Mat3& F, const MaterialFrame* /*frame*/) const override {
    return e_.energy(F);
  }
  Mat3 do_first_piola(const Mat3& F, const MaterialFrame* /*frame*/) const override {
    return e_.first_piola(F);
  }
  Mat3 do_first_piola_derivative(const Mat3& F, const Mat3& dF,
                                 const MaterialFrame* /*frame*/) const override {
    return e_.first_piola_derivative(F, dF);
  }

  NeoHookeanParameters p_;
  StableNeoHookeanEnergy e_;
};

}  // namespace vascsim::materials
