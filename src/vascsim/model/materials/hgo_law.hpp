#pragma once
// Holzapfel-Gasser-Ogden (HGO) law for the arterial wall: Holzapfel, Gasser & Ogden, "A new constitutive
// framework for arterial wall mechanics and a comparative study of material models", J. Elasticity
// 61:1-48, 2000 (open copy: HAL hal-01297725). Compressible form used here:
//
//   psi = psi_ground(F) + sum_{i=4,6} psi_f(I_i)                                       J/m^3
//   psi_ground = mu/2 (I_C - 3) + lambda'/2 (J - alpha)^2 - mu^2/(2 lambda')   (stable neo-Hookean,
//                neo_hookean_law.hpp; lambda' = kappa + mu/3, alpha = 1 + mu/lambda')
//   psi_f(I)   = k1/(2 k2) [exp(k2 (I - 1)^2) - 1]   if I > 1 (fibre in tension), 0 otherwise
//                (k2 = 0: the limit k1/2 (I - 1)^2)
//   I_i = a_i . C a_i = |F a_i|^2   (full, non-isochoric fibre invariants)
//   a_4 = cos(beta) e_theta + sin(beta) e_z,   a_6 = cos(beta) e_theta - sin(beta) e_z
// with (e_z, e_theta, e_r) the node's MaterialFrame: both fibre families lie in the tangent plane of the
// wall at +-beta to the circumferential direction.
//
//   P_f  = 2 psi_f'(I) (F a) a^T,              psi_f'(I)  = k1 (I - 1) exp(k2 (I - 1)^2)
//   dP_f = 2 psi_f''(I) dI (F a) a^T + 2 psi_f'(I) (dF a) a^T,  dI = 2 (F a).(dF a),
//          psi_f''(I) = k1 exp(k2 (I - 1)^2) (1 + 2 k2 (I - 1)^2)      (all zero for I <= 1)
// psi_f' = 0 at I = 1, so P is continuous; psi_f'' jumps there from 0 to k1 (dP is discontinuous at
// I = 1, a kink of the law: finite-difference checks must stay away from it). I - 1 is computed as
// |F a|^2 - |a|^2, which is exactly 0 at F = I, so the rest state deterministically counts as slack and the
// tangent at F = I is that of the ground matrix (with |F a|^2 - 1 the rounding of cos(beta), sin(beta)
// would decide which side of the kink F = I is on).
//
// Choices, and why:
// - Ground matrix: the stable neo-Hookean (with shear modulus mu = c of HGO 2000 and small-strain bulk
//   modulus kappa), not HGO 2000's isochoric mu/2 (Ib1 - 3) + a volumetric penalty. Both agree at J = 1,
//   where HGO 2000's (incompressible) parameters were fitted, but the stable form is defined for every F,
//   including the inverted nodes the meshless model can produce (docs/model/17-limitations.md); and its
//   small-strain response is exactly linear elasticity with (mu, kappa).
// - Fibre invariants: the full I_i = a_i.C a_i, not the isochoric Ib_i = J^(-2/3) I_i of HGO 2000. With
//   Ib_i the fibre term is blind to volume change, so a compressible HGO solid responds isotropically to
//   hydrostatic load (a sphere stays a sphere); Nolan, Gower, Destrade, Ogden & McGarry, "A robust
//   anisotropic hyperelastic formulation for the modelling of soft tissue", J. Mech. Behav. Biomed. Mater.
//   39:48-60, 2014, show this and recommend the full invariants (their "MA" model). The tension switch
//   I_i > 1 then means exactly "the fibre is longer than at rest". I_i = |F a_i|^2 is defined for every F,
//   so with the stable ground matrix the whole law is. For J = 1, I_i = Ib_i and the law is HGO 2000's.
// - The fibres carry load only in tension, as in HGO 2000 (wavy collagen fibres buckle instead of
//   carrying compression), so psi_f = 0 for I_i <= 1.
//
// Parameters (JSON keys): shear_modulus_pa mu (= HGO's c) > 0 (Pa); bulk_modulus_pa kappa > 0 (Pa); k1_pa
// k1 >= 0 (Pa, fibre stiffness); k2 >= 0 (-, fibre exponential stiffening); fibre_angle_deg beta in
// [0, 90] (deg from e_theta towards e_z). Small-strain response (fibres slack at rest): linear elasticity
// with shear modulus mu and bulk modulus kappa; fibres in tension add 4 k1 (a (x) a (x) a (x) a) per family
// to the tangent. Overflow: exp(k2 (I - 1)^2) overflows for k2 (I - 1)^2 > ~709 (e.g. a fibre stretch of ~5.5
// with k2 = 0.84); psi and P are then +inf, far outside physiological stretches (< ~1.5).
//
// Literature parameters (HGO 2000, numerical example: rabbit carotid artery; two layers, incompressible):
//   media:      c = 3.0000 kPa, k1 = 2.3632 kPa, k2 = 0.8393, beta = 29.0 deg
//   adventitia: c = 0.3000 kPa, k1 = 0.5620 kPa, k2 = 0.7112, beta = 62.0 deg
// NOT VERIFIED against the paper text: the search tools available when this was written found the paper
// (HAL hal-01297725) but exposed only its first page, not the example's parameter table. The media values are
// those of the task brief and both layers are as widely reproduced from the paper; check them against the PDF
// before quoting them. The paper treats the wall as incompressible, so kappa is not from the paper: choose
// kappa >> c (e.g. kappa = 2 c (1 + nu)/(3 (1 - 2 nu)) for a ground-matrix Poisson ratio nu = 0.45, i.e.
// kappa = 9.67 c) and state it.

#include "vascsim/model/materials/hyperelastic_law.hpp"
#include "vascsim/model/materials/neo_hookean_law.hpp"

namespace vascsim::materials {

struct HgoParameters {
  double shear_modulus_pa = 0.0;  ///< mu = c, Pa
  double bulk_modulus_pa = 0.0;   ///< kappa, Pa
  double k1_pa = 0.0;             ///< Pa
  double k2 = 0.0;                ///< -
  double fibre_angle_deg = 0.0;   ///< beta, deg from e_theta towards e_z
};

/// HGO 2000 rabbit carotid artery media (c = 3.0 kPa, k1 = 2.3632 kPa, k2 = 0.8393, beta = 29.0 deg;
/// see the header comment for the verification status), with the caller's bulk modulus (Pa).
HgoParameters hgo2000_carotid_media(double bulk_modulus_pa);
/// HGO 2000 rabbit carotid artery adventitia (c = 0.3 kPa, k1 = 0.5620 kPa, k2 = 0.7112, beta = 62.0 deg).
HgoParameters hgo2000_carotid_adventitia(double bulk_modulus_pa);

class HgoLaw final : public HyperelasticLaw {
 public:
  /// Throws InputError naming the parameter if mu <= 0, kappa <= 0, k1 < 0, k2 < 0 or beta outside [0, 90].
  explicit HgoLaw(const HgoParameters& p);

  const HgoParameters& params() const { return p_; }
  /// The ground matrix alone (what the law reduces to when both fibre families are slack).
  const StableNeoHookeanEnergy& ground() const { return ground_; }
  /// Reference fibre directions a_4, a_6 (unit vectors) in a frame.
  Vec3 fibre4(const MaterialFrame& f) const { return cos_beta_ * f.circumferential + sin_beta_ * f.axial; }
  Vec3 fibre6(const MaterialFrame& f) const { return cos_beta_ * f.circumferential - sin_beta_ * f.axial; }

  std::string name() const override { return "hgo"; }
  nlohmann::json parameters() const override;
  std::string reference() const override;
  double small_strain_shear_modulus() const override { return p_.shear_modulus_pa; }
  double small_strain_bulk_modulus() const override { return p_.bulk_modulus_pa; }
  bool needs_frame() const override { return true; }

 private:
  double do_energy_density(const Mat3& F, const MaterialFrame* frame) const override;
  Mat3 do_first_piola(const Mat3& F, const MaterialFrame* frame) const override;
  Mat3 do_first_piola_derivative(const Mat3& F, const Mat3& dF, const MaterialFrame* frame) const override;

  double fibre_energy(const Mat3& F, const Vec3& a) const;
  Mat3 fibre_piola(const Mat3& F, const Vec3& a) const;
  Mat3 fibre_piola_derivative(const Mat3& F, const Mat3& dF, const Vec3& a) const;

  HgoParameters p_;
  StableNeoHookeanEnergy ground_;
  double cos_beta_, sin_beta_;
};

}  // namespace vascsim::materials
