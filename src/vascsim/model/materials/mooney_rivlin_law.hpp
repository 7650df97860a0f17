#pragma once
// Compressible Mooney-Rivlin law with isochoric invariants (Mooney, J. Appl. Phys. 11:582, 1940; Rivlin,
// Phil. Trans. R. Soc. A 241:379, 1948; decoupled compressible form as in Holzapfel, "Nonlinear Solid
// Mechanics", Wiley 2000, Ch. 6):
//
//   psi  = C10 (Ib1 - 3) + C01 (Ib2 - 3) + kappa/2 (J - 1)^2                       J/m^3
//   C = F^T F,  I1 = tr C,  I2 = 1/2 (I1^2 - tr(C^2)),  J = det F > 0,
//   Ib1 = J^(-2/3) I1,  Ib2 = J^(-4/3) I2  (isochoric invariants; Ib1 = Ib2 = 3 for any dilation).
//
// With G = F^{-T} (dJ/dF = J G, dI1/dF = 2F, dI2/dF = 2 (I1 F - F C), d J^(-2/3)/dF = -2/3 J^(-2/3) G):
//   P = 2 C10 J^(-2/3) (F - I1/3 G) + 2 C01 J^(-4/3) (I1 F - F C - 2/3 I2 G) + kappa (J - 1) J G
// dP follows by the product rule with dG = -G dF^T G, dJ = J (G:dF), dI1 = 2 F:dF,
// dI2 = 2 (I1 F - F C):dF, dC = dF^T F + F^T dF (mooney_rivlin_law.cpp).
//
// Small strain: mu = 2 (C10 + C01) (shear modulus), bulk modulus kappa, i.e. the linear elasticity with
// lambda = kappa - 2mu/3, E = 9 kappa mu / (3 kappa + mu), nu = (3 kappa - 2 mu) / (2 (3 kappa + mu)).
//
// Parameters (JSON keys): c10_pa >= 0, c01_pa >= 0 with c10_pa + c01_pa > 0 (Pa); bulk_modulus_pa
// kappa > 0 (Pa). Typical soft tissue: nearly incompressible, kappa >> mu (kappa = 10 mu gives nu = 0.45).
//
// J <= 0 (inverted or collapsed node): the law is undefined there (J^(-2/3) has no real meaning and
// psi -> +infinity as J -> 0+ at fixed I1 > 0). We choose not to throw, because the laws are evaluated
// inside OpenMP parallel regions, from which an exception cannot propagate (std::terminate). Instead:
//   energy_density returns +infinity (the limit J -> 0+), so a backtracking line search rejects the step;
//   first_piola and first_piola_derivative return matrices of quiet NaN, so any force or Hessian-vector
//   sum that used them is NaN and the solvers' finiteness checks fire.
// is_defined(F) (= det F > 0) lets a caller test this without evaluating. Use neo_hookean (or hgo, whose
// ground matrix is the same stable neo-Hookean) where nodes may invert.

#include "vascsim/model/materials/hyperelastic_law.hpp"

namespace vascsim::materials {

struct MooneyRivlinParameters {
  double c10_pa = 0.0;
  double c01_pa = 0.0;
  double bulk_modulus_pa = 0.0;
};

class MooneyRivlinLaw final : public HyperelasticLaw {
 public:
  /// Throws InputError naming the parameter if C10 < 0, C01 < 0, C10 + C01 = 0 or kappa <= 0.
  explicit MooneyRivlinLaw(const MooneyRivlinParameters& p);

  const MooneyRivlinParameters& params() const { return p_; }

  std::string name() const override { return "mooney_rivlin"; }
  nlohmann::json parameters() const override;
  std::string reference() const override;
  double small_strain_shear_modulus() const override { return 2.0 * (p_.c10_pa + p_.c01_pa); }
  double small_strain_bulk_modulus() const override { return p_.bulk_modulus_pa; }
  bool is_defined(const Mat3& F) const override { return F.determinant() > 0.0; }

 private:
  double do_energy_density(const Mat3& F, const MaterialFrame* frame) const override;
  Mat3 do_first_piola(const Mat3& F, const MaterialFrame* frame) const override;
  Mat3 do_first_piola_derivative(const Mat3& F, const Mat3& dF, const MaterialFrame* frame) const override;

  MooneyRivlinParameters p_;
};

}  // namespace vascsim::materials
