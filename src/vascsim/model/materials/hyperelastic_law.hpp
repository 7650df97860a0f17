#pragma once
// Interface of a hyperelastic strain-energy law psi(F) (issue "Vessel-wall materials"). The laws are pure
// functions of the deformation gradient F (F_kl = dx_k/dX_l, docs/model/01-notation.md) and, for anisotropic
// laws, of a per-node MaterialFrame; they know nothing about nodes, volumes or solvers. SI units throughout:
// psi in J/m^3 (= Pa), P in Pa.
//
// Design (why an abstract class and not a std::variant):
// - One law object serves a whole body (or one wall layer). The model holds a `const HyperelasticLaw&`
//   (made once by make_hyperelastic_law, law_factory.hpp) and calls it per node per force evaluation or
//   Hessian-vector product. A call costs one indirect branch (~1-2 ns) next to the ~50-300 flops of the
//   law and ~150 ns per node of force assembly (docs/performance.md); there is no heap allocation per call
//   (all results are fixed-size Eigen matrices returned by value).
// - A std::variant would close the set of laws in this header and make every law a dependency of every
//   user, for a saving that does not show at these costs. If the dispatch ever shows up in a profile, the
//   model can be templated on the concrete law: every law class is `final`, so calls through a concrete
//   type are devirtualised and inlined by the compiler.
// - Per-node anisotropy: the law object is shared and each call takes an optional `const MaterialFrame*`
//   (the node's axial/circumferential/radial triad). Anisotropic laws build their fibre vectors from it
//   (a few flops); isotropic laws ignore it. This keeps the frame law-independent (it comes from the
//   geometry) and avoids one law object per node. needs_frame() tells the caller at set-up whether frames
//   are required; calling an anisotropic law without one is a programming error (std::logic_error).
// - The public evaluation functions are non-virtual wrappers (default argument frame = nullptr) around
//   private virtual hooks, so default arguments are never re-declared on overrides.

#include <nlohmann/json_fwd.hpp>
#include <string>

#include "vascsim/core/types.hpp"
#include "vascsim/model/materials/material_frame.hpp"

namespace vascsim::materials {

class HyperelasticLaw {
 public:
  virtual ~HyperelasticLaw() = default;

  /// Strain-energy density psi(F), J/m^3 (Pa). psi(R) = 0 for every rotation R.
  double energy_density(const Mat3& F, const MaterialFrame* frame = nullptr) const {
    return do_energy_density(F, frame);
  }
  /// First Piola-Kirchhoff stress P = d psi / dF, Pa.
  Mat3 first_piola(const Mat3& F, const MaterialFrame* frame = nullptr) const {
    return do_first_piola(F, frame);
  }
  /// dP = (d^2 psi / dF^2) : dF, the exact directional derivative of P along dF (Pa per unit of dF), for
  /// Hessian-vector products. Symmetric: dF2 : dP(F, dF1) = dF1 : dP(F, dF2).
  Mat3 first_piola_derivative(const Mat3& F, const Mat3& dF, const MaterialFrame* frame = nullptr) const {
    return do_first_piola_derivative(F, dF, frame);
  }

  /// Short identifier, as accepted by make_hyperelastic_law ("svk", "neo_hookean", ...).
  virtual std::string name() const = 0;
  /// The law's input parameters as a JSON object with SI-suffixed keys; make_hyperelastic_law(name(),
  /// parameters()) rebuilds an identical law.
  virtual nlohmann::json parameters() const = 0;
  /// Literature reference of the law (for summary.json).
  virtual std::string reference() const = 0;

  /// Small-strain (linearised at F = I) shear and bulk moduli, Pa. For anisotropic laws: those of the
  /// isotropic ground matrix (fibres are slack at rest).
  virtual double small_strain_shear_modulus() const = 0;
  virtual double small_strain_bulk_modulus() const = 0;

  /// True if the law needs a MaterialFrame at every evaluation.
  virtual bool needs_frame() const { return false; }
  /// True if psi is defined (finite) at F. Laws built on J^(-2/3) (mooney_rivlin) are undefined for
  /// det F <= 0; see each law's header for what it returns there.
  virtual bool is_defined(const Mat3& /*F*/) const { return true; }

  /// {"law": name, "parameters": {...}, "small_strain": {shear/bulk/Young's modulus, Poisson ratio},
  ///  "reference": ...}, for summary.json.
  nlohmann::json to_json() const;

 protected:
  HyperelasticLaw() = default;
  HyperelasticLaw(const HyperelasticLaw&) = default;
  HyperelasticLaw& operator=(const HyperelasticLaw&) = default;

 private:
  virtual double do_energy_density(const Mat3& F, const MaterialFrame* frame) const = 0;
  virtual Mat3 do_first_piola(const Mat3& F, const MaterialFrame* frame) const = 0;
  virtual Mat3 do_first_piola_derivative(const Mat3& F, const Mat3& dF, const MaterialFrame* frame) const = 0;
};

}  // namespace vascsim::materials
